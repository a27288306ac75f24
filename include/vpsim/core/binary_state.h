#pragma once
/// @file
/// A checkpoint's large arrays in one binary file (issue 22: the pictures of a long tiled run, a
/// clustered surface and whole-grid maps of hundreds of MB, which JSON would double and slow):
/// named records of trivially copyable elements, written in one pass and read back by name. The
/// file is a run's private state, never an output: it is written beside the run's files but not
/// through io.h's writers (the manifest must not list it), to a temporary renamed on commit. The
/// same layout can be held in memory (InMemory): an MPI rank's share of the pictures.
///
/// Layout: "VPSIMBS1", then records of (name length u32, name, element size u32, count u64,
/// count x element size bytes), in the writing machine's byte order and struct layout: a
/// checkpoint is resumed by the same vpsim build on machines of one kind (a record whose element
/// size differs is refused; a machine of the other byte order is not detected).

#include <cstdint>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "vpsim/core/sha256.h"

namespace vpsim {

/// Selects the in-memory form of a state: a tile's share of the pictures that an MPI rank sends
/// to rank 0, in the same layout as the file, without a round trip through the disk.
struct InMemory {
    std::string name;  ///< what errors name instead of a file
};

class BinaryStateWriter {
public:
    /// @throw InputError naming `path` when its temporary cannot be opened
    explicit BinaryStateWriter(std::string path);
    /// Writes into memory: commit() then takeBytes() give the bytes a file would hold.
    explicit BinaryStateWriter(InMemory memory);
    ~BinaryStateWriter();
    BinaryStateWriter(const BinaryStateWriter&) = delete;
    BinaryStateWriter& operator=(const BinaryStateWriter&) = delete;

    template <class T>
    void add(const std::string& name, const std::vector<T>& values) {
        static_assert(std::is_trivially_copyable_v<T>);
        addBytes(name, sizeof(T), values.size(), values.data());
    }
    void addBytes(const std::string& name, uint32_t elementSize, uint64_t count, const void* data);
    /// Flushes, checks and renames the temporary to the path.
    /// @throw InputError naming the file when a write failed (disk full?)
    void commit();
    /// After commit: the file's bytes and SHA-256 (hashed as written, not read back).
    uint64_t bytes() const { return mBytes; }
    const std::string& sha256() const { return mSha256; }
    /// After commit, in memory: the state's bytes (moved out).
    std::string takeBytes();

private:
    void write(const void* data, uint64_t bytes);
    std::string mPath, mTemporary;  ///< no temporary in memory
    std::unique_ptr<std::ostream> mOut;
    std::unique_ptr<Sha256> mHash;
    uint64_t mBytes = 0;
    std::string mSha256;
    bool mCommitted = false;
};

class BinaryStateReader {
public:
    /// Reads the records' headers. @throw InputError naming `path` when it is missing, not a
    /// state file or cut short
    explicit BinaryStateReader(std::string path);
    /// Reads a state held in memory (BinaryStateWriter(InMemory)::takeBytes); errors name
    /// `memory.name`. @throw InputError as for a file
    BinaryStateReader(InMemory memory, std::string bytes);

    /// The record `name`. @throw InputError naming the file when there is none, or its elements
    /// are not of T's size
    template <class T>
    std::vector<T> take(const std::string& name) const {
        static_assert(std::is_trivially_copyable_v<T>);
        std::vector<T> values(size_t(count(name, sizeof(T))));
        readBytes(name, values.data());
        return values;
    }
    /// The same, refused unless it holds `expected` elements (a state of another grid).
    template <class T>
    std::vector<T> take(const std::string& name, size_t expected) const {
        checkCount(name, count(name, sizeof(T)), expected);
        return take<T>(name);
    }
    const std::string& path() const { return mPath; }

private:
    struct Record {
        uint64_t offset, count;
        uint32_t elementSize;
    };
    uint64_t count(const std::string& name, uint32_t elementSize) const;
    void readBytes(const std::string& name, void* data) const;
    void checkCount(const std::string& name, uint64_t count, uint64_t expected) const;
    void readHeaders(std::istream& in, uint64_t size);
    std::string mPath;
    std::map<std::string, Record> mRecords;
    std::shared_ptr<const std::string> mBytes;  ///< the state in memory, or null: in mPath
};

}  // namespace vpsim
