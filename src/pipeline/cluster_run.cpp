#include "vpsim/pipeline/cluster_run.h"

#include "vpsim/cluster/communicator.h"
#include "vpsim/transport/mc_split.h"

namespace vpsim::pipeline {
namespace {

/// How one Monte Carlo kernel's work was shared.
nlohmann::json kernelSplit(const char* kernel, const std::optional<kernel::BeamKernel>& table,
                           bool fromCache, int ranks) {
    if (!table) return nullptr;
    if (fromCache)
        return {{"kernel", kernel}, {"what", "nothing: rank 0 read the kernel from the cache"}};
    nlohmann::json split = transport::photonSplitJson(table->photons, ranks);
    split["kernel"] = kernel;
    return split;
}

}  // namespace

void runJobOnWorkerRank(const Job& job, const RunContext& context) {
    beamStage(job, context);  // runJob's only collective stage
}

nlohmann::json clusterSummary(const BeamResult& beam, const RunContext& context) {
    if (!context.cluster || context.cluster->ranks() <= 1) return nullptr;
    const int ranks = context.cluster->ranks();
    nlohmann::json split = nlohmann::json::array();
    for (const nlohmann::json& s :
         {kernelSplit("kernel", beam.monteCarlo, beam.fromCache, ranks),
          kernelSplit("kernel.plan", beam.planMonteCarlo, beam.planFromCache, ranks)})
        if (!s.is_null()) split.push_back(s);
    return {{"ranks", ranks},
            {"split", split},
            {"rank_0",
             "the stages after the beam kernel (slice, plan, exposure, cure, validation, "
             "report) and every file written"}};
}

}  // namespace vpsim::pipeline
