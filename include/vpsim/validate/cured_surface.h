#pragma once
/// @file
/// The cured part's surface: the iso-surface of the stored exposure where the cure law flips
/// (its critical dose), triangulated with outward normals, in mm.

#include "vpsim/cure/cure_law.h"
#include "vpsim/exposure/dose_volume.h"
#include "vpsim/geometry/mesh.h"

namespace vpsim::validate {

/// @throw InputError when nothing cures (the exposure never reaches the critical dose)
geometry::Mesh curedSurface(const exposure::DoseVolume& exposure, const cure::CureLaw& law);

}  // namespace vpsim::validate
