// The x-z section's row: chosen from the material of every layer together, so an overhang part
// whose middle layer is only its pillars is still cut through its overhang.
#include <catch2/catch.hpp>

#include "vpsim/report/figures.h"

using namespace vpsim;

TEST_CASE("the x-z section's row crosses the most material of all layers", "[report]") {
    exposure::ExposureGrid grid;
    grid.nx = 100, grid.ny = 100, grid.pitch = 0.01;  // 1 mm x 1 mm
    // Two thin pillars in every layer (rows 10-19), and a wide overhang on top of them in two
    // layers (rows 60-79): the pillars are the most in one layer, the overhang in the part.
    const auto pillars = geometry::PolygonSet::rectangle({0.0, 0.1}, {0.1, 0.2})
                             .unite(geometry::PolygonSet::rectangle({0.8, 0.1}, {0.9, 0.2}));
    const auto overhang = geometry::PolygonSet::rectangle({0.0, 0.6}, {1.0, 0.8});
    std::vector<geometry::PolygonSet> layers(4, pillars);
    layers.push_back(overhang);
    layers.push_back(overhang);
    const int row = report::busiestRow(layers, grid);
    CHECK(row >= 60);
    CHECK(row < 80);
    CHECK(row == 70);  // the middle of the tied rows, not the overhang's edge
    // The same layers in another order (a cross-section that comes back after another one).
    const std::vector<geometry::PolygonSet> interleaved = {pillars,  overhang, pillars,
                                                           overhang, pillars,  pillars};
    CHECK(report::busiestRow(interleaved, grid) == 70);
    // Repeats that are not neighbours: every layer is still counted.
    CHECK(report::busiestRow({pillars, pillars, overhang, pillars, pillars, overhang}, grid) == 70);
    // Each pillar layer counts: 20 columns x 10 of them (rows 10-19) beat one overhang's 100.
    std::vector<geometry::PolygonSet> mostlyPillars(10, pillars);
    mostlyPillars.push_back(overhang);
    CHECK(report::busiestRow(mostlyPillars, grid) == 15);
    // One layer alone: its own busiest rows.
    CHECK(report::busiestRow({pillars}, grid) == 15);
    // No material at all: the middle row.
    CHECK(report::busiestRow({geometry::PolygonSet()}, grid) == 50);
}
