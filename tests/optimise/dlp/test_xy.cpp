// xy coupling: the blur operator's adjoint (<A x, y> = <x, A^T y>) and the joint optimisation
// never worse than the column optimum seen through the same blur.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "dlp_test_support.h"
#include "vpsim/optimise/dlp/xy.h"

using namespace vpsim::optimise;
using vpsim::test::seedResin;

namespace {}  // namespace

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

namespace {

/// A thin wall (2 pixels wide, 14 long) on a pillar, with a down-facing ledge: pixels x 3..4 are
/// solid from layer 0, the ledge x 5..8 only from layer 8 (its underside faces down).
DlpLayerStack wallWithLedge() {
    DlpLayerStack part;
    part.width = 12, part.height = 6;
    part.layers.assign(14, std::vector<uint8_t>(72, 0));
    for (int k = 0; k < 14; ++k)
        for (int y = 1; y < 5; ++y)
            for (int x = 3; x < 9; ++x) part.layers[k][y * 12 + x] = x <= 4 || k >= 8;
    return part;
}

}  // namespace

TEST_CASE("xy: the shape objective's gradient equals finite differences", "[optimise]") {
    // J is piecewise quadratic in the doses; central differences with a step of 1e-3 of the dose
    // are exact up to float rounding of the fields (5e-3 relative, or 1e-6 of the gradient's
    // largest entry).
    DlpLayerStack part = wallWithLedge();
    DlpXyOptions o;
    DlpShapeObjective j(part, seedResin(), o, 2.0);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.3f, 1.3f);
    std::vector<std::vector<float>> d(14, std::vector<float>(72, 0.0f));
    for (int k = 0; k < 14; ++k)
        for (int p = 0; p < 72; ++p)
            if (part.layers[k][p]) d[k][p] = u(rng);
    std::vector<std::vector<float>> g;
    j.value(d, &g);
    double largest = 0.0;
    for (const auto& l : g)
        for (float v : l) largest = std::max(largest, double(std::abs(v)));
    for (auto [k, p] : {std::pair<int, int>{0, 15}, {8, 18}, {13, 19}, {9, 29}, {7, 16}}) {
        const float h = 1e-3f * std::max(d[k][p], 0.1f);
        auto plus = d, minus = d;
        plus[k][p] += h, minus[k][p] -= h;
        const double fd = (j.value(plus) - j.value(minus)) / (2.0 * double(h));
        INFO("layer " << k << " pixel " << p << " fd " << fd << " adjoint " << g[k][p]);
        REQUIRE(std::abs(fd - g[k][p]) <= 5e-3 * std::abs(fd) + 1e-6 * largest);
    }
}

TEST_CASE("xy: joint optimum never worse than its warm start, keeps Eq. 10", "[optimise]") {
    DlpLayerStack part = wallWithLedge();
    for (DlpObjective objective : {DlpObjective::ConversionL2, DlpObjective::Geometric}) {
        DlpPartOptions o;
        o.problem = seedResin();
        o.objective = objective;
        DlpXyOptions xy;
        xy.iterations = 30;
        DlpPartResult columns = optimiseDlpPart(part, o);
        DlpXyResult r = optimiseDlpPartXy(part, o, xy, &columns);
        // J evaluated anew, on its own objective, for the column optimum and the result.
        DlpShapeObjective j(part, o.problem, xy, r.uniformityTarget);
        const double start = j.value(columns.dose), end = j.value(r.doses.dose);
        INFO("J columns " << start << " start " << r.objectiveStart << " xy " << end << " from "
                          << r.start);
        REQUIRE(end <= start);
        REQUIRE(end <= r.objectiveStart * (1 + 1e-12));
        REQUIRE(end == Approx(r.objectiveXy).epsilon(1e-9));
        // Every pixel's doses are printable: 0 on void, Eq. 10 for its own pattern, <= d_max.
        for (int px = 0; px < 72; ++px) {
            std::vector<uint8_t> solid(14), exposed(14);
            for (int k = 0; k < 14; ++k) {
                solid[k] = part.layers[k][px];
                exposed[k] = r.doses.dose[k][px] > 0.0f;
                if (!solid[k]) REQUIRE(r.doses.dose[k][px] == 0.0f);
            }
            std::vector<double> lo, hi;
            REQUIRE(exposureBounds(exposed, solid, o.problem, lo, hi));
            for (int k = 0; k < 14; ++k) {
                REQUIRE(r.doses.dose[k][px] >= float(lo[k]) * (1 - 1e-6f));
                REQUIRE(r.doses.dose[k][px] <= float(hi[k]) * (1 + 1e-6f));
            }
        }
    }
}

TEST_CASE("xy: a thin wall with a down-facing ledge keeps its XY size better", "[optimise]") {
    // The XY contour error (mid-depth of every layer, through the same blur) of the joint optimum
    // is below the column optimum's, for the paper's objective and for the geometric one.
    DlpLayerStack part = wallWithLedge();
    for (DlpObjective objective : {DlpObjective::ConversionL2, DlpObjective::Geometric}) {
        DlpPartOptions o;
        o.problem = seedResin();
        o.objective = objective;
        DlpXyOptions xy;
        xy.iterations = 30;
        DlpXyResult r = optimiseDlpPartXy(part, o, xy);
        INFO("contour error columns " << r.contourErrorColumns << " xy " << r.contourErrorXy);
        REQUIRE(r.contourErrorXy < r.contourErrorColumns);
    }
}
