// Print-through along Z (seed 001 Eq. 4, seed 000 Eq. 21): recursion vs direct sum, closed forms.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "vpsim/core/error.h"
#include "vpsim/cure/print_through.h"

using namespace vpsim;
using namespace vpsim::cure;

TEST_CASE("Accumulated layer doses: recursion equals the direct sum", "[cure]") {
    // 300 layers with random greyscale doses (fixed seed), some zero (voids). The recursion and the
    // direct sum add the same terms in a different order: agreement to 1e-12 relative.
    std::mt19937 rng(2024);
    std::uniform_real_distribution<double> uniform(0.0, 1.5);
    std::vector<double> doses(300);
    for (size_t i = 0; i < doses.size(); ++i) doses[i] = (i % 37 < 5) ? 0.0 : uniform(rng);
    const double le = 0.05, dp = 0.366;
    std::vector<double> top = accumulatedLayerDoses(doses, le, dp);
    std::vector<double> bottom = accumulatedBottomDoses(doses, le, dp);
    REQUIRE(top.size() == doses.size());
    for (size_t i = 0; i < doses.size(); ++i) {
        double direct = 0.0;  // explicit sum of Eq. 4 terms over the layers exposed after i
        for (size_t j = i; j < doses.size(); ++j)
            direct += doses[j] * std::exp(-double(j - i) * le / dp);
        REQUIRE(top[i] == Approx(direct).epsilon(1e-12));
        REQUIRE(accumulatedDoseAtHeight(doses, le, dp, (i + 1) * le) ==
                Approx(direct).epsilon(1e-12));
        // The bottom of layer i lies one layer thickness below its top.
        REQUIRE(bottom[i] == Approx(direct * std::exp(-le / dp)).epsilon(1e-12));
        REQUIRE(accumulatedDoseAtHeight(doses, le, dp, i * le + 1e-9) ==
                Approx(direct * std::exp(-(le - 1e-9) / dp)).epsilon(1e-12));
    }
}

TEST_CASE("Print-through of uniform layers approaches the geometric series", "[cure]") {
    // d0 per layer: D_i = d0 (1 - a^(n-i)) / (1 - a), a = exp(-Le/Dp), the stepped profile of
    // Fig. 3.
    const double d0 = 0.78, le = 0.05, dp = 0.366, a = std::exp(-le / dp);
    const size_t n = 120;
    std::vector<double> top = accumulatedLayerDoses(std::vector<double>(n, d0), le, dp);
    for (size_t i = 0; i < n; ++i)
        REQUIRE(top[i] ==
                Approx(d0 * (1.0 - std::pow(a, double(n - i))) / (1.0 - a)).epsilon(1e-12));
    // Monotonic: the first layers receive the most dose (seed 001 Section 2.3).
    for (size_t i = 1; i < n; ++i) REQUIRE(top[i - 1] > top[i]);
    // The second layer's exposure adds Eq. 4's Delta d_2 = d0 exp(-mu Le) to the first layer.
    std::vector<double> two = accumulatedLayerDoses({d0, d0}, le, dp);
    REQUIRE(two[0] - d0 == Approx(printThroughDose(d0, le, dp)).epsilon(1e-14));
}

TEST_CASE("Print-through is linear in the layer doses", "[cure]") {
    std::vector<double> a = {0.1, 0.0, 0.7, 0.3}, b = {0.5, 0.2, 0.0, 0.9}, sum(4);
    for (int i = 0; i < 4; ++i) sum[i] = 2.0 * a[i] + b[i];
    auto da = accumulatedLayerDoses(a, 0.025, 0.1), db = accumulatedLayerDoses(b, 0.025, 0.1),
         ds = accumulatedLayerDoses(sum, 0.025, 0.1);
    for (int i = 0; i < 4; ++i) REQUIRE(ds[i] == Approx(2.0 * da[i] + db[i]).epsilon(1e-14));
}

TEST_CASE("Print-through refuses bad stacks", "[cure]") {
    REQUIRE_THROWS_AS(accumulatedLayerDoses({0.1, -0.2}, 0.05, 0.3), InputError);
    REQUIRE_THROWS_WITH(accumulatedLayerDoses({0.1, -0.2}, 0.05, 0.3), Catch::Contains("layer 1"));
    REQUIRE_THROWS_AS(accumulatedLayerDoses({0.1}, 0.0, 0.3), InputError);
    REQUIRE_THROWS_AS(accumulatedLayerDoses({0.1}, 0.05, -1.0), InputError);
    REQUIRE_THROWS_AS(accumulatedDoseAtHeight({0.1, NAN}, 0.05, 0.3, 0.0), InputError);
    REQUIRE(accumulatedLayerDoses({}, 0.05, 0.3).empty());
}
