#include <catch2/catch.hpp>

#include <filesystem>

#include "vpsim/pipeline/run_job.h"

using namespace vpsim;

// Seed 001 Table 2, non-optimised prints: the simulated hole heights and overhang thicknesses
// (uniform 78 mJ/cm^2 DLP masks, resin calibrated on Table 1) beside the measured ones. The
// paper's own model was within -0.06 +- 0.11 mm of its prints; vpsim claims each feature within
// 0.2 mm of the mean of the three prints, and requires the over-cure direction: holes shrink and
// overhangs thicken, by more than half of the measured change. Measured (simulated - printed,
// mm): top hole 0.71 - 0.903 = -0.193, bottom hole 2.21 - 2.27 = -0.06, top overhang +0.143,
// bottom overhang +0.093; the top hole is the closest to the claim (0.007 mm inside it).
TEST_CASE("seed 001 Table 2 Z dimensions are reproduced", "[pipeline][slow][seed001]") {
    for (const char* name : {"seed001-holes", "seed001-overhangs"}) {
        pipeline::Job job =
            pipeline::loadJob(std::string(VPSIM_SOURCE_DIR) + "/examples/" + name + ".json",
                              pipeline::makeBuiltins());
        auto out = std::filesystem::temp_directory_path() / name;
        report::JobResult r = pipeline::runJob(job, out.string(), RunContext{});
        const validate::FeatureMeasurements& features = r.validation.features;
        REQUIRE(features.probes.size() == 2);
        for (size_t i = 0; i < features.probes.size(); ++i) {
            const validate::FeatureProbe& feature = features.probes[i];
            double simulated = features.simulated[i], objective = feature.objective;
            double measured = 0;
            for (double m : feature.measured) measured += m / double(feature.measured.size());
            INFO(name << ": " << feature.name << " simulated " << simulated << " measured "
                      << measured);
            CHECK(std::abs(simulated - measured) <= 0.2);
            CHECK((simulated - objective) * (measured - objective) > 0);
            CHECK(std::abs(simulated - objective) > 0.5 * std::abs(measured - objective));
        }
    }
}
