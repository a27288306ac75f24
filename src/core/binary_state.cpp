#include "vpsim/core/binary_state.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>

#include <unistd.h>

#include "vpsim/core/error.h"

namespace vpsim {
namespace {

constexpr char MAGIC[8] = {'V', 'P', 'S', 'I', 'M', 'B', 'S', '1'};
constexpr uint32_t MAX_NAME = 256;

template <class T>
bool get(std::istream& in, T& value) {
    return bool(in.read(reinterpret_cast<char*>(&value), sizeof value));
}

}  // namespace

BinaryStateWriter::BinaryStateWriter(std::string path)
    : mPath(std::move(path)), mTemporary(mPath + ".tmp." + std::to_string(getpid())) {
    mOut = std::make_unique<std::ofstream>(mTemporary, std::ios::binary | std::ios::trunc);
    if (!*mOut) throw InputError("cannot open for writing", mTemporary);
    mHash = std::make_unique<Sha256>();
    write(MAGIC, sizeof MAGIC);
}

BinaryStateWriter::BinaryStateWriter(InMemory memory) : mPath(std::move(memory.name)) {
    mOut = std::make_unique<std::ostringstream>(std::ios::binary);
    mHash = std::make_unique<Sha256>();
    write(MAGIC, sizeof MAGIC);
}

std::string BinaryStateWriter::takeBytes() {
    auto* memory = dynamic_cast<std::ostringstream*>(mOut.get());
    if (!mCommitted || !memory) throw Error("BinaryStateWriter::takeBytes: no committed memory");
    std::string bytes = std::move(*memory).str();
    memory->str({});
    return bytes;
}

void BinaryStateWriter::write(const void* data, uint64_t bytes) {
    mOut->write(static_cast<const char*>(data), std::streamsize(bytes));
    mHash->update(data, bytes);
    mBytes += bytes;
}

BinaryStateWriter::~BinaryStateWriter() {
    if (mCommitted || mTemporary.empty()) return;
    mOut.reset();
    std::remove(mTemporary.c_str());
}

void BinaryStateWriter::addBytes(const std::string& name, uint32_t elementSize, uint64_t count,
                                 const void* data) {
    const uint32_t nameSize = uint32_t(name.size());
    write(&nameSize, sizeof nameSize);
    write(name.data(), nameSize);
    write(&elementSize, sizeof elementSize);
    write(&count, sizeof count);
    if (count) write(data, count * elementSize);
}

void BinaryStateWriter::commit() {
    if (mCommitted) return;
    mOut->flush();
    const bool good = bool(*mOut);
    mCommitted = true;
    mSha256 = mHash->hex();
    if (mTemporary.empty()) {  // in memory
        if (!good) throw InputError("cannot hold the state in memory", mPath);
        return;
    }
    auto& file = static_cast<std::ofstream&>(*mOut);
    file.close();
    if (!good || !file) {
        std::remove(mTemporary.c_str());
        throw InputError("cannot write the checkpoint (disk full?)", mPath);
    }
    std::error_code error;
    std::filesystem::rename(mTemporary, mPath, error);
    if (error) throw InputError("cannot write the checkpoint: " + error.message(), mPath);
}

BinaryStateReader::BinaryStateReader(std::string path) : mPath(std::move(path)) {
    std::ifstream in(mPath, std::ios::binary);
    if (!in) throw InputError("cannot open the checkpoint's state", mPath);
    std::error_code error;
    readHeaders(in, std::filesystem::file_size(mPath, error));
}

BinaryStateReader::BinaryStateReader(InMemory memory, std::string bytes)
    : mPath(std::move(memory.name)), mBytes(std::make_shared<const std::string>(std::move(bytes))) {
    std::istringstream in(*mBytes, std::ios::binary);
    readHeaders(in, mBytes->size());
}

void BinaryStateReader::readHeaders(std::istream& in, uint64_t size) {
    char magic[sizeof MAGIC];
    if (!in.read(magic, sizeof magic) || std::memcmp(magic, MAGIC, sizeof MAGIC) != 0)
        throw InputError("not a vpsim checkpoint state file", mPath);
    uint64_t at = sizeof MAGIC;
    while (at < size) {
        uint32_t nameSize = 0, elementSize = 0;
        uint64_t count = 0;
        std::string name;
        bool good = get(in, nameSize) && nameSize <= MAX_NAME;
        if (good) {
            name.resize(nameSize);
            good = bool(in.read(name.data(), nameSize)) && get(in, elementSize) && get(in, count) &&
                   elementSize > 0;
        }
        at += sizeof nameSize + nameSize + sizeof elementSize + sizeof count;
        // The record must fit in what is left of the file (a cut file is refused here).
        if (!good || count > (size - std::min(size, at)) / elementSize)
            throw InputError("malformed checkpoint state (a record is cut short)", mPath);
        mRecords[name] = {at, count, elementSize};
        at += count * elementSize;
        in.seekg(std::streamoff(at));
    }
}

uint64_t BinaryStateReader::count(const std::string& name, uint32_t elementSize) const {
    const auto it = mRecords.find(name);
    if (it == mRecords.end())
        throw InputError("malformed checkpoint state (no '" + name + "')", mPath);
    if (it->second.elementSize != elementSize)
        throw InputError("malformed checkpoint state ('" + name + "' has elements of " +
                             std::to_string(it->second.elementSize) + " bytes, not " +
                             std::to_string(elementSize) + ")",
                         mPath);
    return it->second.count;
}

void BinaryStateReader::checkCount(const std::string& name, uint64_t count,
                                   uint64_t expected) const {
    if (count != expected)
        throw InputError("malformed checkpoint state ('" + name + "' holds " +
                             std::to_string(count) + " values, this run's " +
                             std::to_string(expected) + ")",
                         mPath);
}

void BinaryStateReader::readBytes(const std::string& name, void* data) const {
    const Record& record = mRecords.at(name);
    if (record.count == 0) return;
    if (mBytes) {  // readHeaders checked that the record lies inside the bytes
        std::memcpy(data, mBytes->data() + record.offset,
                    size_t(record.count * record.elementSize));
        return;
    }
    std::ifstream in(mPath, std::ios::binary);
    in.seekg(std::streamoff(record.offset));
    if (!in.read(static_cast<char*>(data), std::streamsize(record.count * record.elementSize)))
        throw InputError("malformed checkpoint state ('" + name + "' cut short)", mPath);
}

}  // namespace vpsim
