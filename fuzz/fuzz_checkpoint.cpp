// libFuzzer target: a checkpoint's binary state file (core/binary_state.h), read back as the
// picture of a cured surface (validate::SurfaceClusters::restore), the largest record a resumed
// run reads from DIR/checkpoint/pictures-N.bin, and, read from memory as rank 0 reads an MPI
// rank's tile (BinaryStateReader(InMemory)), merged into a picture (SurfaceClusters::merge).
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
        // The same bytes from memory: the same records (a file's reader accepted them).
        std::string bytes(reinterpret_cast<const char*>(data), size);
        const vpsim::BinaryStateReader fromMemory(vpsim::InMemory{"fuzz"}, std::move(bytes));
        vpsim::validate::SurfaceClusters clusters(0.05);
        clusters.restore(in, "cured.clusters");
        const vpsim::geometry::Mesh mesh = clusters.mesh();
        for (const auto& tri : mesh.triangles)
            for (uint32_t v : tri)
                if (v >= mesh.vertices.size()) __builtin_trap();  // restore checked them
        vpsim::validate::SurfaceClusters merged(0.05);
        merged.add({0.01, 0.01, 0.01}, 1.0f);
        merged.endTile();
        merged.merge(fromMemory, "cured.clusters");
        const vpsim::geometry::Mesh both = merged.mesh();
        for (const auto& tri : both.triangles)
            for (uint32_t v : tri)
                if (v >= both.vertices.size() || tri[0] == tri[1] || tri[1] == tri[2] ||
                    tri[0] == tri[2])
                    __builtin_trap();  // merge checked them
        try {
            // As words: a map of floats may hold NaN, which equals nothing.
            if (in.take<uint32_t>("sections.map") != fromMemory.take<uint32_t>("sections.map"))
                __builtin_trap();  // one record, two readers
        } catch (const vpsim::Error&) {}
    } catch (const vpsim::Error&) {}
    return 0;
}
