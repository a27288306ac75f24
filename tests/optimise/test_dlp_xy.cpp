// xy coupling: the blur operator's adjoint (<A x, y> = <x, A^T y>) and the joint optimisation
// never worse than the column optimum seen through the same blur.
#include <catch2/catch.hpp>

#include <random>

#include "vpsim/optimise/dlp_xy.h"

using namespace vpsim::optimise;

namespace {

DlpColumnProblem seedResin() {
    DlpColumnProblem p;
    p.rateConstant = 0.528080236;
    p.attenuation = 1.0 / 0.365935872;
    p.gelPoint = 0.276;
    p.maxDose = 1.3;
    return p;
}

}  // namespace

TEST_CASE("xy: blur operator adjoint <A x, y> = <x, A^T y>", "[optimise]") {
    // Random x (pixels) and y (cells); float fields, sums in double: 1e-5 relative.
    DlpXyOptions o;
    o.subsamples = 3;
    DlpBlurOperator op(5, 4, 6, seedResin(), o);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<std::vector<float>> x(6, std::vector<float>(20)),
        y(6, std::vector<float>(size_t(op.cellsX()) * op.cellsY()));
    for (auto& l : x)
        for (float& v : l) v = u(rng);
    for (auto& l : y)
        for (float& v : l) v = u(rng) - 0.5f;
    auto ax = op.apply(x);
    auto aty = op.applyAdjoint(y);
    double left = 0.0, right = 0.0;
    for (size_t k = 0; k < 6; ++k) {
        for (size_t c = 0; c < y[k].size(); ++c) left += double(ax[k][c]) * y[k][c];
        for (size_t p = 0; p < 20; ++p) right += double(x[k][p]) * aty[k][p];
    }
    REQUIRE(left == Approx(right).epsilon(1e-5));
}

TEST_CASE("xy: joint optimum improves F through the blur and keeps the boxes", "[optimise]") {
    // A 4 x 4 pixel pillar of 12 layers on 8 void layers... an overhang: pixels (1..2, 1..2)
    // solid from layer 0, the ring only from layer 6 (a down-facing ledge).
    DlpLayerStack part;
    part.width = part.height = 4;
    part.layers.assign(12, std::vector<uint8_t>(16, 0));
    for (int k = 0; k < 12; ++k)
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x) {
                bool core = x >= 1 && x <= 2 && y >= 1 && y <= 2;
                part.layers[k][y * 4 + x] = core || k >= 6;
            }
    DlpPartOptions o;
    o.problem = seedResin();
    DlpXyOptions xy;
    xy.iterations = 40;
    DlpPartResult columns = optimiseDlpPart(part, o);
    DlpXyResult r = optimiseDlpPartXy(part, o, xy, &columns);
    INFO("F columns " << r.objectiveColumns << " xy " << r.objectiveXy);
    REQUIRE(r.objectiveXy <= r.objectiveColumns);
    for (int k = 0; k < 12; ++k)
        for (int p = 0; p < 16; ++p) {
            REQUIRE(r.doses.dose[k][p] <= 1.3f * (1 + 1e-6f));
            if (!part.layers[k][p]) REQUIRE(r.doses.dose[k][p] == 0.0f);
            // the exposure pattern is kept
            REQUIRE((r.doses.dose[k][p] > 0.0f) == (columns.dose[k][p] > 0.0f));
        }
}
