#include "vpsim/exposure/surface_grid.h"

namespace vpsim::exposure {

double SurfaceGrid::totalEnergy() const {
    double sum = 0;
    for (float v : values) sum += v;
    return sum * pitch * pitch;
}

}  // namespace vpsim::exposure
