#include <catch2/catch.hpp>

#include "vpsim/core/registry.h"

using namespace vpsim;

namespace {
struct Widget {
    double size = 0;
};
}  // namespace

TEST_CASE("a registry creates components by name from their section and names the known ones") {
    Registry<Widget> registry("widget");
    registry.add({"square", "a square widget", {{"size", "side, mm"}}, [](const ConfigNode& s) {
                      auto w = std::make_unique<Widget>();
                      w->size = s.number("size", 1.0);
                      return w;
                  }});
    REQUIRE(registry.has("square"));
    REQUIRE(registry.names() == std::vector<std::string>{"square"});
    ConfigNode section(nlohmann::json{{"size", 2.5}}, "job.json");
    REQUIRE(registry.create("square", section)->size == 2.5);
    try {
        registry.create("round", section);
        FAIL("expected an InputError");
    } catch (const InputError& e) {
        REQUIRE(std::string(e.what()).find("unknown widget 'round' (known: square)") !=
                std::string::npos);
    }
    REQUIRE_THROWS_AS(registry.add({"square", "", {}, nullptr}), std::logic_error);
}
