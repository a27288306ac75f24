#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>

#include "support/svg_text.h"
#include "vpsim/exposure/surface_grid.h"
#include "vpsim/geometry/polygons.h"
#include "vpsim/optimise/laser/exposure_figures.h"

using namespace vpsim;

TEST_CASE("the Etar line of an exposure map is drawn through the hatch ripple's average",
          "[optimise][figures]") {
    // A 4 mm square hatched at 40 um: inside, the exposure ripples +-10% about Etar; outside it
    // falls to 0 over 0.1 mm. The raw Etar line crosses every ripple (two lines per hatch line,
    // 200 in all); the 0.9 Etar line of the map averaged over 100 um squares is the edge alone.
    const double pitch = 0.01, etar = 0.2, period = 0.04;
    exposure::SurfaceGrid map(500, 500, -0.5, -0.5, pitch);
    for (int j = 0; j < map.ny; ++j)
        for (int i = 0; i < map.nx; ++i) {
            const double x = map.centreX(i), y = map.centreY(j);
            const double outside = std::max({-x, x - 4.0, -y, y - 4.0, 0.0});
            const double ripple = 1 + 0.1 * std::cos(2 * M_PI * x / period);
            map.values[size_t(j) * map.nx + i] =
                float(etar * ripple * std::max(0.0, 1 - outside / 0.1));
        }
    const auto region = geometry::PolygonSet::rectangle({0, 0}, {4, 4});
    const auto dir = std::filesystem::temp_directory_path() / "vpsim_exposure_figures";
    std::filesystem::create_directories(dir);
    optimise::writeExposureMapFigure((dir / "raw").string(), "raw", map, &region, etar, 0.1);
    optimise::writeExposureMapFigure((dir / "smoothed").string(), "smoothed", map, &region, etar,
                                     0.1, 0.1);
    const auto raw = std::filesystem::file_size(dir / "raw.svg");
    const auto smoothed = std::filesystem::file_size(dir / "smoothed.svg");
    INFO("raw " << raw << " B, smoothed " << smoothed << " B");
    CHECK(smoothed * 3 < raw);
    const std::string svg = test::readWhole((dir / "smoothed.svg").string());
    CHECK(test::hasText(svg, "averaged over 100 um squares"));
    CHECK(test::hasText(svg, "0.9 E"));
    CHECK(test::hasText(svg, "model outline"));
}
