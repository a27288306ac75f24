// libFuzzer target: the STL reader (binary and ASCII detection and parsing) and the mesh checks
// and repairs every reader applies. Any exception other than vpsim::Error is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "vpsim/core/error.h"
#include "vpsim/geometry/mesh_check.h"
#include "vpsim/geometry/stl_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    try {
        vpsim::geometry::Mesh mesh = vpsim::geometry::parseStlSoup(bytes, "fuzz.stl");
        if (mesh.triangles.size() > 20000) return 0;  // keep each run fast
        vpsim::geometry::MeshCheckOptions options;
        options.throwOnProblem = false;
        (void)vpsim::geometry::checkMesh(mesh, "fuzz.stl", options);
    } catch (const vpsim::Error&) {}
    return 0;
}
