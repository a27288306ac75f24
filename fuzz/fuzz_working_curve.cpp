// libFuzzer target: the working-curve CSV reader (header units, cells, line numbers).
#include <cstddef>
#include <cstdint>
#include <string>

#include "vpsim/core/error.h"
#include "vpsim/cure/calibration.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        (void)vpsim::cure::parseWorkingCurveCsv(text, "fuzz.csv");
    } catch (const vpsim::Error&) {}
    return 0;
}
