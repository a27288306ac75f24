#include "vpsim/kernel/kernel_spec.h"

#include "vpsim/core/checks.h"
#include "vpsim/core/config.h"
#include "vpsim/transport/photon_mc.h"

namespace vpsim::kernel {

KernelSpec kernelSpecFromConfig(const ConfigNode& kernel, bool allowPlan) {
    KernelSpec spec;
    if (allowPlan && kernel.has("plan"))
        spec.plan = std::make_shared<KernelSpec>(kernelSpecFromConfig(kernel.child("plan"), false));
    std::string source =
        kernel.choice("source", {"monte-carlo", "given"}, std::string("monte-carlo"));
    if (source == "monte-carlo") {
        long long photons = kernel.integer("photons", 300000);
        if (photons < 1000 || uint64_t(photons) > transport::MAX_PHOTONS)
            throw kernel.error("photons", "expected 1000 .. 1e12");
        spec.photons = uint64_t(photons);
        spec.seed = uint32_t(kernel.integer("seed", 1));
        spec.tabulated =
            kernel.choice("use", {"fitted", "tabulated"}, std::string("fitted")) == "tabulated";
        if (kernel.has("estimator"))
            spec.estimator =
                transport::parseEstimator(kernel.string("estimator"), kernel.keyPath("estimator"));
        return spec;
    }
    spec.source = KernelSource::Given;
    spec.given.radius = positiveQuantity(kernel, "We3D", dim::LENGTH, 0.05);
    spec.given.attenuationLength = positiveQuantity(kernel, "De3D", dim::LENGTH, 0.1);
    spec.given.depthOfMaximum = kernel.quantity("zmax", dim::LENGTH, 0.0);
    if (!(spec.given.depthOfMaximum >= 0)) throw kernel.error("zmax", "must not be negative");
    spec.given.efficiency = kernel.numberInRange("efficiency", 1e-6, 10.0, 1.0);
    return spec;
}

}  // namespace vpsim::kernel
