#pragma once
/// @file
/// Checks and safe repairs of triangle meshes read from STL files.
///
/// Safe repairs (each one is logged with logWarn and listed in MeshReport::repairs):
///  - duplicate vertices are merged (exact coordinate equality, as STL repeats each vertex);
///  - triangles that repeat a vertex after merging (zero area) are dropped;
///  - inconsistent triangle orientation is fixed by flood-fill across shared edges;
///  - a shell whose volume has the wrong sign (inside-out) is flipped; a shell nested inside an
///    odd number of others is a cavity and is oriented inward. Nesting is decided by ray parity
///    from seven probe points on the shell (a centroid and its extreme vertices); a shell that only
///    overlaps another (a self-intersecting union) is not nested and stays outward, and slicing
///    then merges the overlap.
/// Not repairable (an InputError naming the file, the count and the first location):
///  open edges (not watertight), non-manifold edges (used by more than two triangles), a
///  non-orientable shell, zero enclosed volume. Zero-area triangles with three distinct vertices
///  (collinear slivers) are kept and reported: dropping them would open the mesh, and they do not
///  change the shape or the slices.

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/geometry/mesh.h"

namespace vpsim::geometry {

/// What checkMesh() found and did.
struct MeshReport {
    std::string file;        ///< name used in messages
    size_t trianglesIn = 0;  ///< triangles before repair
    size_t verticesIn = 0;   ///< vertices before merging (3 per STL triangle)
    size_t duplicateVerticesMerged = 0;
    size_t degenerateTrianglesDropped = 0;  ///< triangles repeating a vertex
    size_t sliverTrianglesKept = 0;         ///< zero-area triangles with distinct vertices
    size_t trianglesReoriented = 0;         ///< flipped to agree with their neighbours
    size_t shellsFlipped = 0;               ///< inside-out shells turned around
    size_t openEdges = 0;
    size_t nonManifoldEdges = 0;
    size_t shells = 0;    ///< connected components
    double volume = 0.0;  ///< mm^3 after repair
    double area = 0.0;    ///< mm^2
    Bounds bounds;
    std::vector<std::string> repairs;   ///< one human line per repair done
    std::vector<std::string> problems;  ///< unrepairable defects (empty for an accepted mesh)

    bool ok() const { return problems.empty(); }
    nlohmann::json toJson() const;
};

/// Options of checkMesh().
struct MeshCheckOptions {
    bool repair = true;  ///< apply the safe repairs (otherwise they are reported as problems)
    bool throwOnProblem = true;  ///< throw InputError for the first unrepairable problem
};

/// Merges vertices with bit-identical coordinates (+0 and -0 are equal) and remaps triangles.
/// @return the number of vertices removed
size_t mergeDuplicateVertices(Mesh& mesh);

/// Checks a mesh and applies the safe repairs in place (see file comment).
/// @param name file name used in messages
/// @throw InputError "NAME: 12 open edges (mesh is not watertight), first near (x, y, z) mm" for
///        an unrepairable defect when options.throwOnProblem
MeshReport checkMesh(Mesh& mesh, const std::string& name, const MeshCheckOptions& options = {});

}  // namespace vpsim::geometry
