#pragma once
// Private to the modules that write OpenVDB files (transport, kernel, geometry, exposure): one
// initialisation and one atomic, error-checked write. Include only from .cpp files that already
// include OpenVDB (docs/PLATFORM.md: OpenVDB headers are expensive).

#include <mutex>
#include <string>

#include <openvdb/openvdb.h>

#include "vpsim/core/error.h"
#include "vpsim/core/io.h"

namespace vpsim::vdb {

/// openvdb::initialize(), once per process (it registers grid types; calling it again is
/// harmless but not free, and not thread safe against concurrent readers).
inline void initialise() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

/// Writes `grids` to `path` atomically (a temporary renamed into place).
/// @throw InputError naming the file when OpenVDB or the file system fails
inline void writeGrids(const std::string& path, const openvdb::GridPtrVec& grids) {
    writePathAtomic(path, [&](const std::string& temporary) {
        try {
            openvdb::io::File file(temporary);
            file.write(grids);
            file.close();
        } catch (const openvdb::Exception& e) {
            throw InputError(std::string("cannot write OpenVDB file: ") + e.what(), path);
        }
    });
}

}  // namespace vpsim::vdb
