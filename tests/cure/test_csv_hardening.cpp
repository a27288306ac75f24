// Working-curve CSV: decimal numbers only, out-of-range cells refused, quoted text escaped.
#include <catch2/catch.hpp>

#include "vpsim/core/error.h"
#include "vpsim/cure/calibration.h"

using namespace vpsim;
using namespace vpsim::cure;
using Catch::Matchers::Contains;

namespace {

std::string messageOf(const std::string& text) {
    try {
        parseWorkingCurveCsv(text, "w.csv");
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no InputError)";
}

const char* HEADER = "dose_mJ_per_cm2,thickness_mm\n";

}  // namespace

TEST_CASE("working-curve cells are decimal numbers in range", "[cure][csv]") {
    CHECK_THAT(messageOf(std::string(HEADER) + "10,0.1\n0x14,0.2\n40,0.3\n"),
               Contains("w.csv:3: non-numeric cell '0x14'"));
    CHECK_THAT(messageOf(std::string(HEADER) + "10,0.1\ninf,0.2\n40,0.3\n"),
               Contains("non-numeric cell 'inf'"));
    CHECK_THAT(messageOf(std::string(HEADER) + "10,0.1\n1e400,0.2\n40,0.3\n"),
               Contains("w.csv:3") && Contains("out of range"));
    CHECK_THAT(messageOf(std::string(HEADER) + "10,0.1\n20,\x01\xff\n40,0.3\n"),
               Contains("'\\x01\\xFF'"));
    const std::string longCell =
        std::string(HEADER) + "10,0.1\n20," + std::string(5000, '9') + "x\n40,0.3\n";
    CHECK(messageOf(longCell).size() < 300);
    CHECK_THAT(messageOf(std::string(HEADER) + "10,0.1\n20,0.2\n40,0.3\n"),
               Contains("no InputError"));
}
