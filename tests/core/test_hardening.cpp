// Bad input to the core readers: every case ends in one InputError naming the file and key, with
// user text escaped and cut; limits on nesting, strings, numbers; decimal-only numbers; bounded
// reads; clear output errors.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/text.h"
#include "vpsim/core/units.h"

using namespace vpsim;
using Catch::Matchers::Contains;

namespace {

std::string writeTemp(const std::string& name, const std::string& text) {
    auto path = std::filesystem::temp_directory_path() / ("vpsim_hardening_" + name);
    std::ofstream(path, std::ios::binary) << text;
    return path.string();
}

std::string errorOf(const std::function<void()>& action) {
    try {
        action();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

bool printable(const std::string& text) {
    for (unsigned char c : text)
        if (c < 0x20 || c == 0x7F) return false;
    return true;
}

}  // namespace

TEST_CASE("messages escape control bytes and invalid UTF-8 and cut long text", "[core][text]") {
    CHECK(escaped("a\nb\tc\x01") == "a\\nb\\tc\\x01");
    CHECK(escaped("caf\xC3\xA9 \xB5m") == "caf\xC3\xA9 \\xB5m");  // valid UTF-8 kept
    CHECK(escaped("\xC0\xAF") == "\\xC0\\xAF");                   // overlong form refused
    CHECK(escaped(std::string(1000, 'x')).size() == MESSAGE_QUOTE_LIMIT + 3);
    CHECK(quoteUser("it") == "'it'");
    const InputError error("bad", std::string(1000, 'p') + "\n", "key\x1b[31m");
    CHECK(printable(error.what()));
    CHECK(std::string(error.what()).size() < 400);
}

TEST_CASE("quantities for people: about 4 significant digits, no trailing zeros", "[core][text]") {
    CHECK(formatQuantity(78.0, "mJ/cm^2") == "78 mJ/cm^2");
    CHECK(formatQuantity(1.0, "mm") == "1 mm");
    CHECK(formatQuantity(0.35, "mm") == "0.35 mm");
    CHECK(formatQuantity(0.1 + 0.2) == "0.3");
    CHECK(formatQuantity(12345.6, "s") == "12346 s");  // integer digits are never cut
    CHECK(formatQuantity(9.99996) == "10");
    CHECK(formatQuantity(-0.00001234, "mm") == "-1.234e-05 mm");
    CHECK(formatQuantity(-1e-9 * 1e-9) == "-1e-18");
    CHECK(formatQuantity(0.0, "mW") == "0 mW");
    CHECK(formatQuantity(-0.00004) == "-4e-05");
    CHECK(formatQuantity(-0.0001) == "-0.0001");
    CHECK(formatQuantity(2.0 / 3.0, "", 2) == "0.67");
}

TEST_CASE("numbers are decimal only", "[core][units]") {
    CHECK(parseDecimal("1.5e-3") == Approx(1.5e-3));
    CHECK(parseDecimal(".5") == Approx(0.5));
    CHECK_FALSE(parseDecimal("0x10"));
    CHECK_FALSE(parseDecimal("inf"));
    CHECK_FALSE(parseDecimal("nan"));
    CHECK_FALSE(parseDecimal("1e"));
    CHECK_FALSE(parseDecimal(""));
    CHECK_THROWS_WITH(parseQuantity("0x10 mm", dim::LENGTH, "part.size", "job.json"),
                      Contains("job.json: key 'part.size'") && Contains("decimal digits only"));
    CHECK_THROWS_AS(parseQuantity("inf mm", dim::LENGTH), InputError);
    CHECK_THROWS_AS(parseQuantity("1e300 m", dim::LENGTH), InputError);
    CHECK(parseQuantity("1e3 um", dim::LENGTH) == Approx(1.0));
    CHECK(parseQuantity("-2.5", dim::LENGTH) == Approx(-2.5));
}

TEST_CASE("the JSON reader refuses deep nesting, long strings, huge numbers, duplicates",
          "[core][config]") {
    const std::string deep = writeTemp(
        "deep.json", "{\"a\":" + std::string(100000, '[') + "1" + std::string(100000, ']') + "}");
    CHECK_THAT(errorOf([&] { loadJsonFile(deep); }), Contains("nested more than 64"));
    const std::string deepObjects = [] {
        std::string text;
        for (int i = 0; i < 100000; ++i) text += "{\"a\":";
        text += "1";
        for (int i = 0; i < 100000; ++i) text += "}";
        return text;
    }();
    CHECK_THAT(errorOf([&] { parseJsonText(deepObjects, "deep2.json"); }),
               Contains("deep2.json:1: JSON nested"));

    CHECK_THAT(errorOf([] { parseJsonText(R"({"cure": {"dose": 1e400}})", "j.json"); }),
               Contains("j.json: key 'cure.dose'") && Contains("out of range"));
    CHECK_THAT(errorOf([] { parseJsonText(R"({"a": [1, 2, -1e19]})", "j.json"); }),
               Contains("key 'a[2]'") && Contains("out of range"));
    CHECK_THAT(errorOf([] { parseJsonText(R"({"m": {"x": 1, "x": 2}})", "j.json"); }),
               Contains("key 'm.x'") && Contains("duplicate key"));
    CHECK_NOTHROW(
        parseJsonText(R"({"m": {"x": 1}, "n": {"x": 2}, "l": [{"x": 1}, {"x": 2}]})", "ok.json"));
    const std::string longString = "{\"name\": \"" + std::string(10'000'000, 'x') + "\"}";
    const std::string message = errorOf([&] { parseJsonText(longString, "j.json"); });
    CHECK_THAT(message, Contains("key 'name'") && Contains("longer than the 4096"));
    CHECK(message.size() < 200);
    // A syntax error quoting binary bytes stays one printable line.
    const std::string binary = errorOf([] { parseJsonText("{\"a\": \x01\n\xff}", "b.json"); });
    CHECK_THAT(binary, Contains("b.json:1: malformed JSON"));
    CHECK(printable(binary));
}

TEST_CASE("--set values obey the same limits", "[core][config]") {
    nlohmann::json document = nlohmann::json::object();
    CHECK_THROWS_WITH(applyOverride(document, "machine.layer_thickness=1e400"),
                      Contains("out of range"));
    CHECK_THROWS_WITH(applyOverride(document, "a=" + std::string(100, '[')),
                      Contains("nested more than"));
    applyOverride(document, "part.size=0x10 mm");  // a string; the units reader refuses it
    CHECK(document["part"]["size"] == "0x10 mm");
    CHECK_THROWS_WITH(applyOverride(document, "a=" + std::string(5000, 'x')),
                      Contains("longer than"));
}

TEST_CASE("config messages quoting user values are cut and escaped", "[core][config]") {
    ConfigNode node(nlohmann::json{{"mode", std::string(5000, 'y') + "\n"}, {"n", "\x01"}},
                    "c.json");
    const std::string choice = errorOf([&] { node.choice("mode", {"a", "b"}); });
    CHECK(choice.size() < 250);
    CHECK(printable(choice));
    CHECK_THAT(errorOf([&] { node.integer("n"); }), Contains("'\\x01'"));
}

TEST_CASE("reads are bounded by size and refuse devices", "[core][io]") {
    CHECK_THAT(errorOf([] { readFile("/dev/zero"); }), Contains("not a regular file"));
    CHECK_THAT(errorOf([] { readFile("/nonexistent/vpsim/file"); }), Contains("cannot read file"));
    const std::string path = writeTemp("big.txt", std::string(5000, 'b'));
    CHECK_THAT(errorOf([&] { readFile(path, 1000); }), Contains("larger than the"));
    CHECK(readFile(path, 5000).size() == 5000);
    CHECK_THAT(errorOf([] { readFile(std::string(5000, 'n')); }), Contains("File name too long"));
    CHECK(errorOf([] { readFile(std::string(5000, 'n')); }).size() < 300);
}

TEST_CASE("writing to a directory or a missing directory says so", "[core][io]") {
    const std::string dir = std::filesystem::temp_directory_path().string();
    CHECK_THAT(errorOf([&] { writeFileAtomic(dir, "x"); }), Contains("is a directory"));
    CHECK_THAT(errorOf([] { writeFileAtomic("/nonexistent/vpsim/out.stl", "x"); }),
               Contains("does not exist"));
}

TEST_CASE("HTML escaping leaves no markup and no control bytes", "[core][text]") {
    CHECK(htmlEscape("<script>alert('x')</script> & \"q\"") ==
          "&lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt; &amp; &quot;q&quot;");
    CHECK(htmlEscape("caf\xC3\xA9\x01\xff") == "caf\xC3\xA9\xEF\xBF\xBD\xEF\xBF\xBD");
}
