#include "vpsim/kernel/kernel_arguments.h"

#include "vpsim/core/error.h"
#include "vpsim/core/text.h"
#include "vpsim/core/units.h"

namespace vpsim::kernel {

KernelOptions kernelOptions(const KernelArguments& a, const transport::ArgumentName& name) {
    auto positive = [&](const std::string& text, Dimension dimension, const std::string& key) {
        const double v = parseQuantity(text, dimension, name(key));
        if (!(v > 0)) throw InputError("must be > 0, got " + quoteUser(text), "", name(key));
        return v;
    };
    KernelOptions o;
    o.power = positive(a.power, dim::POWER, "power");
    o.w0 = parseQuantity(a.w0, dim::LENGTH, name("w0"));
    if (!(o.w0 > 0.0 && o.w0 <= 100.0))
        throw InputError("must be in (0, 100] mm, got " + quoteUser(a.w0), "", name("w0"));
    o.photons = transport::parsePhotonCount(a.photons, name("photons"));
    o.seed = a.seed;
    if (!a.thickness.empty()) o.thickness = positive(a.thickness, dim::LENGTH, "thickness");
    o.nOutside = a.nOutside;
    if (!a.rMax.empty()) o.rMax = positive(a.rMax, dim::LENGTH, "r_max");
    if (!a.zMax.empty()) o.zMax = positive(a.zMax, dim::LENGTH, "z_max");
    if (a.bins < 4 || a.bins > 1000)
        throw InputError("expected 4..1000, got " + std::to_string(a.bins), "", name("bins"));
    o.bins = a.bins;
    o.estimator = transport::parseEstimator(a.estimator, name("estimator"));
    return o;
}

}  // namespace vpsim::kernel
