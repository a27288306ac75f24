#pragma once
/// @file
/// A job's `part` section: an STL file (with a scale) or a parametric test part, and loading it
/// onto the build platform (its lowest point at z = 0). A mesh made in code (the Python module's
/// vertex and triangle arrays) takes the section's place.
///   {"stl": "parts/l-shape.stl", "scale": 1}
///   {"test_part": "holes", "size": "10 mm", "height": "5 mm", ...}

#include <memory>
#include <string>

#include "vpsim/geometry/mesh.h"
#include "vpsim/geometry/test_parts.h"

namespace vpsim {
class ConfigNode;
}

namespace vpsim::geometry {

struct PartSpec {
    std::string stl;       ///< resolved STL path, or "" for a test part
    double scale = 1.0;    ///< applied to the STL's coordinates (e.g. 25.4 for inches)
    std::string testPart;  ///< test part name when stl is ""
    TestPartOptions testPartOptions;
    /// A mesh given in code, already checked (checkMesh), used instead of stl and testPart.
    std::shared_ptr<const Mesh> mesh;
    /// A name for messages and reports: the STL path, "test part NAME" or "part arrays".
    std::string source() const {
        if (mesh) return "part arrays";
        return stl.empty() ? "test part " + testPart : stl;
    }
};

/// Reads a `part` section; paths are relative to the section's file.
/// @throw InputError naming the file and key (both or neither of stl/test_part, missing file)
PartSpec partSpecFromConfig(const ConfigNode& section);

/// The part's mesh, checked and repaired as readStl() does, moved so its lowest z is 0.
/// @throw InputError for unreadable or broken STL files
Mesh loadPart(const PartSpec& spec);

}  // namespace vpsim::geometry
