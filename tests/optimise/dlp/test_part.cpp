// Whole-part DLP optimisation: distinct columns solved once, each pixel gets its profile's doses.
#include <catch2/catch.hpp>

#include "vpsim/optimise/dlp/part.h"

using namespace vpsim::optimise;

TEST_CASE("DLP part: columns with the same profile share one solve", "[optimise]") {
    // 6 x 4 pixels, 10 layers: a block (all layers) on the left half, an overhang (layers 5-9)
    // on the right half, one empty column. Three profiles -> two distinct solves (empty skipped).
    DlpLayerStack part;
    part.width = 6, part.height = 4;
    part.layers.assign(10, std::vector<uint8_t>(24, 0));
    for (int k = 0; k < 10; ++k)
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 6; ++x)
                if ((x < 3 || k >= 5) && !(x == 5 && y == 3)) part.layers[k][y * 6 + x] = 1;
    DlpPartOptions o;
    o.problem.rateConstant = 0.528080236;
    o.problem.attenuation = 1.0 / 0.365935872;
    o.problem.gelPoint = 0.276;
    o.problem.maxDose = 1.3;
    DlpPartResult r = optimiseDlpPart(part, o);
    REQUIRE(r.distinctColumns == 2);
    REQUIRE(r.maxGap <= 1e-9);
    DlpSearchResult left = solveColumnExactly(columnProfile(part, 0, 0), o.problem);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 3; ++x) {
            std::vector<double> d = columnDoses(r, x, y);
            for (int k = 0; k < 10; ++k) REQUIRE(d[k] == Approx(left.best.dose[k]).epsilon(1e-6));
        }
    for (int k = 0; k < 10; ++k) REQUIRE(r.dose[k][3 * 6 + 5] == 0.0f);  // empty column
    for (int k = 0; k < 5; ++k) REQUIRE(r.dose[k][0 * 6 + 4] == 0.0f);   // void below overhang
}
