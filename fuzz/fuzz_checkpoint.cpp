// libFuzzer target: a checkpoint's binary state file (core/binary_state.h), read back as the
// picture of a cured surface (validate::SurfaceClusters::restore), the largest record a resumed
// run reads from DIR/checkpoint/pictures-N.bin, and merged into a picture as rank 0 merges an MPI
// rank's tile (SurfaceClusters::merge).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

#include "vpsim/core/binary_state.h"
#include "vpsim/core/error.h"
#include "vpsim/validate/surface_clusters.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::string path = "/tmp/vpsim_fuzz_checkpoint." + std::to_string(getpid());
    std::ofstream(path, std::ios::binary | std::ios::trunc)
        .write(reinterpret_cast<const char*>(data), std::streamsize(size));
    try {
        const vpsim::BinaryStateReader in(path);
        vpsim::validate::SurfaceClusters clusters(0.05);
        clusters.restore(in, "cured.clusters");
        const vpsim::geometry::Mesh mesh = clusters.mesh();
        for (const auto& tri : mesh.triangles)
            for (uint32_t v : tri)
                if (v >= mesh.vertices.size()) __builtin_trap();  // restore checked them
        vpsim::validate::SurfaceClusters merged(0.05);
        merged.add({0.01, 0.01, 0.01}, 1.0f);
        merged.endTile();
        merged.merge(in, "cured.clusters");
        const vpsim::geometry::Mesh both = merged.mesh();
        for (const auto& tri : both.triangles)
            for (uint32_t v : tri)
                if (v >= both.vertices.size() || tri[0] == tri[1] || tri[1] == tri[2] ||
                    tri[0] == tri[2])
                    __builtin_trap();  // merge checked them
        (void)in.take<float>("sections.map");
    } catch (const vpsim::Error&) {}
    return 0;
}
