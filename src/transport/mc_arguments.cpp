#include "vpsim/transport/mc_arguments.h"

#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/core/resources.h"
#include "vpsim/core/text.h"
#include "vpsim/core/units.h"

namespace vpsim::transport {

uint64_t parsePhotonCount(const std::string& text, const std::string& key) {
    // Decimal only ("1e6" is fine; "0x10", "inf" and "nan" are not counts).
    const std::optional<double> n = parseDecimal(text);
    if (!n || !(*n >= 1) || *n > double(MAX_PHOTONS) || *n != std::floor(*n))
        throw InputError("expected a whole number from 1 to " + std::to_string(MAX_PHOTONS) +
                             ", got " + quoteUser(text),
                         "", key);
    return uint64_t(*n);
}

McSetup mcSetup(const McArguments& a, const optics::MediumOptics& optics, const ArgumentName& name,
                const RunContext& context) {
    auto length = [&](const std::string& text, const std::string& key) {
        return parseQuantity(text, dim::LENGTH, name(key));
    };
    McSetup s;
    s.optics = optics;
    s.photons = parsePhotonCount(a.photons, name("photons"));
    s.seed = a.seed;
    s.estimator = parseEstimator(a.estimator, name("estimator"));
    s.rouletteThreshold = a.roulette;
    s.thickness = a.thickness.empty() ? 0.0 : length(a.thickness, "thickness");
    if (!a.thickness.empty() && !(s.thickness > 0))
        throw InputError("must be > 0 (leave it out for a semi-infinite medium)", "",
                         name("thickness"));
    s.nAbove = s.nBelow = a.nOutside;
    if (a.beam != "pencil" && a.beam != "gaussian")
        throw InputError("expected 'pencil' or 'gaussian', got " + quoteUser(a.beam), "",
                         name("beam"));
    s.beam = a.beam == "gaussian" ? BeamShape::Gaussian : BeamShape::Pencil;
    s.w0 = length(a.w0, "w0");
    if (!(s.w0 > 0.0 && s.w0 <= 100.0))
        throw InputError("must be in (0, 100] mm, got " + quoteUser(a.w0), "", name("w0"));
    s.beamConvolution = !a.directBeam;
    s.controlVariates = a.controlVariates;
    for (const std::string& d : a.depths) s.depths.push_back(length(d, "depths"));
    s.bins.rMax = length(a.rMax, "r_max");
    s.bins.zMax = length(a.zMax, "z_max");
    s.bins.rBins = s.bins.zBins = a.bins;
    if (!a.voxel.empty()) {
        s.grid.voxel = length(a.voxel, "voxel");
        if (!(s.grid.voxel > 0)) throw InputError("must be > 0", "", name("voxel"));
        // Sized in double and checked in bytes before the uint32 casts could wrap.
        const double nxy = std::ceil(2 * s.bins.rMax / s.grid.voxel);
        const double nz = std::ceil(s.bins.zMax / s.grid.voxel);
        checkMemory(context, nxy * nxy * nz * 8.0,
                    "the absorption grid at " + name("voxel") + " " + a.voxel,
                    "use a coarser " + name("voxel") + " or a smaller " + name("r_max") + "/" +
                        name("z_max"));
        if (nxy > 65536 || nz > 65536)
            throw ResourceError(
                "the absorption grid needs more than 65536 voxels along an axis: "
                "use a coarser " +
                name("voxel"));
        s.grid.nxy = uint32_t(nxy);
        s.grid.nz = uint32_t(nz);
    }
    return s;
}

}  // namespace vpsim::transport
