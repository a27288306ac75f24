#include <catch2/catch.hpp>

#include "vpsim/core/registry.h"

using namespace vpsim;
using Catch::Matchers::Contains;

namespace {
struct Widget {
    double size = 0;
    std::string colour;
};

KeyTable widgetKeys() {
    return {{quantityKey("size", dim::LENGTH, "1 mm", "side").positiveOnly().in(0, 10),
             choiceKey("colour", {"red", "blue"}, "red", "paint")}};
}

std::unique_ptr<Widget> makeWidget(const KeyReader& keys) {
    auto w = std::make_unique<Widget>();
    w->size = keys.quantity("size");
    w->colour = keys.choice("colour");
    return w;
}
}  // namespace

TEST_CASE("a registry creates components by name from their section and names the known ones") {
    Registry<Widget> registry("widget");
    registry.add({"square", "a square widget", widgetKeys(), makeWidget});
    REQUIRE(registry.has("square"));
    REQUIRE(registry.names() == std::vector<std::string>{"square"});
    ConfigNode section(nlohmann::json{{"size", "2.5 mm"}}, "job.json");
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

TEST_CASE("a key table gives defaults, ranges and docs from one declaration", "[core][keys]") {
    const KeyTable table = widgetKeys();
    ConfigNode empty(nlohmann::json::object(), "job.json");
    auto w = makeWidget(KeyReader(table, empty, "widget 'square'"));
    CHECK(w->size == 1.0);  // "1 mm" from the table
    CHECK(w->colour == "red");
    ConfigNode big(nlohmann::json{{"size", "2 cm"}}, "job.json");
    CHECK_THROWS_WITH(makeWidget(KeyReader(table, big, "widget 'square'")),
                      Contains("job.json") && Contains("size") && Contains("outside"));
    ConfigNode zero(nlohmann::json{{"size", 0}}, "job.json");
    CHECK_THROWS_WITH(makeWidget(KeyReader(table, zero, "widget 'square'")),
                      Contains("must be positive"));
    // Reading a key the table does not declare is a programming error.
    KeyReader keys(table, empty, "widget 'square'");
    CHECK_THROWS_AS(keys.number("weight"), std::logic_error);
    // The table's documentation.
    const nlohmann::json doc = table.toJson();
    REQUIRE(doc.size() == 2);
    CHECK(doc[0]["name"] == "size");
    CHECK(doc[0]["default"] == "1 mm");
    CHECK(doc[0]["dimension"] == dim::LENGTH.describe());
    CHECK(doc[0]["doc"] == "side");
    CHECK(doc[1]["choices"] == nlohmann::json{"red", "blue"});
    CHECK_THAT(table.markdown(), Contains("| `size` | `\"1 mm\"` |"));
    CHECK_THROWS_AS(KeyTable({numberKey("a", 1, ""), numberKey("a", 2, "")}), std::logic_error);
}

TEST_CASE("unknown keys name the owner and the nearest accepted key", "[core][keys]") {
    CHECK(nearestKey("homogenity", {"edge", "homogeneity", "order"}) == "homogeneity");
    CHECK(nearestKey("Size", {"size"}) == "size");
    CHECK(nearestKey("xyz", {"homogeneity"}).empty());  // nothing close
    ConfigNode root(nlohmann::json{{"widget", {{"colur", "red"}}}}, "job.json");
    makeWidget(KeyReader(widgetKeys(), root.child("widget"), "widget 'square'"));
    CHECK_THROWS_WITH(root.checkUnknownKeys(), Contains("widget.colur") &&
                                                   Contains("widget 'square'") &&
                                                   Contains("did you mean 'colour'?"));
}
