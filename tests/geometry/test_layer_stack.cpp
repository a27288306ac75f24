// LayerStack JSON: exact round trip and clear errors for malformed files.
#include <catch2/catch.hpp>

#include "test_util.h"
#include "vpsim/core/error.h"
#include "vpsim/geometry/layer_stack.h"
#include "vpsim/geometry/test_parts.h"

using namespace vpsim;
using namespace vpsim::geometry;
using Catch::Matchers::Contains;

TEST_CASE("layer stack saves and loads back exactly", "[stack]") {
    SliceOptions options;
    options.layerThickness = 0.5;
    TestPartOptions o;
    o.segments = 33;
    const LayerStack stack = sliceToStack(makeTestPart("cylinder", o), options, "cylinder");
    const std::string path = test::tempPath("stack.json");
    stack.save(path);
    const LayerStack back = LayerStack::load(path);
    CHECK(back.source == "cylinder");
    CHECK(back.layerThickness == 0.5);
    CHECK(back.zStart == 0.0);
    REQUIRE(back.layers.size() == stack.layers.size());
    for (size_t k = 0; k < stack.layers.size(); ++k) {
        CHECK(back.layers[k].z == stack.layers[k].z);
        CHECK(back.layers[k].region.area() ==
              stack.layers[k].region.area());  // exact: same 1 nm grid
        CHECK(back.layers[k].region.outerCount() == 1);
    }
    // Holes survive the round trip.
    const LayerStack ring = sliceToStack(makeTestPart("holes"), options, "holes", {5});
    const LayerStack ringBack = LayerStack::fromJson(ring.toJson());
    CHECK(ringBack.layers.at(0).region.area() == ring.layers.at(0).region.area());
}

TEST_CASE("malformed layer stacks are clear errors", "[stack][bad-input]") {
    const std::string path = test::tempPath("bad_stack.json");
    test::writeBytes(path, R"({"format": "something else"})");
    CHECK_THROWS_WITH(LayerStack::load(path),
                      Contains("bad_stack.json") && Contains("not a layer stack"));
    test::writeBytes(
        path,
        R"({"format": "vpsim-layer-stack", "version": 1, "source": "x", "layer_thickness_mm": 0.05,
        "plane_position": 0.5, "z_start_mm": 0, "layers": [{"index": 0, "z": 0.025, "z_bottom": 0,
        "parts": [{"outer": [[0, 0], [1, "a"], [0, 1]]}]}]})");
    CHECK_THROWS_WITH(LayerStack::load(path), Contains("layers[0].parts[0].outer"));
    test::writeBytes(path, R"({"format": "vpsim-layer-stack", "version": 1, "layers": []})");
    CHECK_THROWS_WITH(LayerStack::load(path), Contains("layer_thickness_mm"));
}
