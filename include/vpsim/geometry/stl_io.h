#pragma once
/// @file
/// STL files in and out. The format (binary or ASCII) is detected from the content, never from
/// the extension: a binary file whose size is exactly 84 + 50 * (its triangle count) is binary
/// even when its 80-byte header begins with "solid" (many exporters write that).

#include <string>

#include "vpsim/geometry/mesh.h"
#include "vpsim/geometry/mesh_check.h"

namespace vpsim::geometry {

/// Options of readStl().
struct StlReadOptions {
    double scale = 1.0;      ///< multiplies coordinates; 1 for files in mm, 25.4 for inches
    MeshCheckOptions check;  ///< checks and repairs applied after reading
};

/// Triangle soup as stored in the file (3 vertices per triangle, no sharing), scaled to mm.
/// @throw InputError naming the file for: unreadable file, truncated binary file, a triangle
///        count that disagrees with the file size, malformed ASCII (with line number), NaN or
///        infinite coordinates (with triangle number), zero triangles
Mesh readStlSoup(const std::string& path, double scale = 1.0);
/// The same from the bytes of an STL file; `name` names it in messages (the fuzz target's entry).
Mesh parseStlSoup(const std::string& data, const std::string& name, double scale = 1.0);

/// Reads an STL file, merges vertices and checks/repairs the mesh (see mesh_check.h).
/// Repairs are logged with logWarn and returned in `report` when given.
/// @throw InputError naming the file and the reason for anything not safely repairable
Mesh readStl(const std::string& path, const StlReadOptions& options = {},
             MeshReport* report = nullptr);
/// readStl() with the default checks and repairs, coordinates multiplied by `scale` (to mm).
Mesh readStl(const std::string& path, double scale);

/// Writes a binary STL (atomically: temp file then rename), with facet normals.
/// @param solidName written into the 80-byte header (never starting with "solid")
/// @throw InputError when the file cannot be written
void writeStl(const std::string& path, const Mesh& mesh, const std::string& solidName = "vpsim");

/// Writes an ASCII STL (atomically); meant for tests and hand inspection.
void writeStlAscii(const std::string& path, const Mesh& mesh,
                   const std::string& solidName = "vpsim");

}  // namespace vpsim::geometry
