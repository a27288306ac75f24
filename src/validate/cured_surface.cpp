#include "vpsim/validate/cured_surface.h"

#include "vpsim/core/error.h"
#include "vpsim/core/text.h"

namespace vpsim::validate {

geometry::Mesh curedSurface(const exposure::DoseVolume& exposure, const cure::CureLaw& law) {
    geometry::Mesh cured = exposure.isosurface(float(law.criticalDose()));
    if (cured.triangles.empty())
        throw InputError("nothing cured: the exposure never reaches the critical dose (" +
                         formatQuantity(law.criticalDose() * 100.0) + " mJ/cm^2)");
    return cured;
}

}  // namespace vpsim::validate
