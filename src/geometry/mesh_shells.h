#pragma once
// Connected shells of a triangle mesh, for checkMesh (internal to the geometry module).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "vpsim/geometry/mesh.h"
#include "vpsim/geometry/mesh_check.h"

namespace vpsim::geometry::detail {

/// "(x, y, z) mm", for messages that point at a place in the mesh.
std::string formatPoint(const glm::dvec3& p);

struct Shell {
    std::vector<uint32_t> triangles;
    Bounds bounds;
    double volume = 0.0;
    int depth = 0;  // number of other shells enclosing this one
};

/// Flood-fills a consistent orientation per connected shell. flip[t] says whether triangle t
/// must be reversed to agree with its shell's first triangle; a non-orientable shell is reported
/// as a problem.
std::vector<Shell> orientShells(const Mesh& mesh,
                                const std::vector<std::array<int64_t, 3>>& neighbours,
                                const std::vector<std::array<bool, 3>>& sameDirection,
                                std::vector<char>& flip, MeshReport& report);

/// Signed volume of a shell with the flood-fill orientation applied, mm^3.
double shellVolume(const Mesh& mesh, const Shell& shell, const std::vector<char>& flip);

/// Nesting depth of each shell by ray parity; an odd depth is a cavity (oriented inward).
void computeDepths(const Mesh& mesh, std::vector<Shell>& shells);

}  // namespace vpsim::geometry::detail
