// A run's binary state (core/binary_state.h) in a file and in memory: the same bytes, the same
// records read back, and malformed states refused with the name they were given.
#include <catch2/catch.hpp>

#include <filesystem>

#include "vpsim/core/binary_state.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"

using namespace vpsim;

namespace {

void addRecords(BinaryStateWriter& out) {
    out.add("floats", std::vector<float>{1.5f, -2.0f, 0.25f});
    out.add("empty", std::vector<uint64_t>{});
    out.add("words", std::vector<uint32_t>{7, 8, 9, 10});
}

}  // namespace

TEST_CASE("a binary state in memory holds the file's bytes and reads back the same records",
          "[core]") {
    const std::string path =
        (std::filesystem::temp_directory_path() / "vpsim_test_binary_state.bin").string();
    BinaryStateWriter file(path);
    addRecords(file);
    file.commit();
    BinaryStateWriter memory(InMemory{"a tile's pictures"});
    addRecords(memory);
    memory.commit();
    CHECK(memory.sha256() == file.sha256());
    CHECK(memory.bytes() == file.bytes());
    const std::string bytes = memory.takeBytes();
    CHECK(bytes == readFile(path));

    const BinaryStateReader fromFile(path), fromMemory(InMemory{"a tile's pictures"}, bytes);
    for (const BinaryStateReader* in : {&fromFile, &fromMemory}) {
        CHECK(in->take<float>("floats") == std::vector<float>{1.5f, -2.0f, 0.25f});
        CHECK(in->take<uint64_t>("empty").empty());
        CHECK(in->take<uint32_t>("words", 4) == std::vector<uint32_t>{7, 8, 9, 10});
        CHECK_THROWS_AS(in->take<double>("floats"), InputError);  // 4-byte elements
        CHECK_THROWS_AS(in->take<uint32_t>("words", 5), InputError);
        CHECK_THROWS_AS(in->take<float>("missing"), InputError);
    }
    CHECK_THROWS_WITH(fromMemory.take<float>("missing"), Catch::Contains("a tile's pictures"));
    std::filesystem::remove(path);

    // Cut anywhere inside the last record, or not a state at all: refused, naming the state.
    for (size_t cut : {bytes.size() - 1, bytes.size() - 16, size_t(12)})
        CHECK_THROWS_WITH(BinaryStateReader(InMemory{"rank 1's tile 3"}, bytes.substr(0, cut)),
                          Catch::Contains("rank 1's tile 3"));
    CHECK_THROWS_WITH(BinaryStateReader(InMemory{"rank 1's tile 3"}, "not a state"),
                      Catch::Contains("not a vpsim checkpoint state"));
}

TEST_CASE("a memory state's bytes are taken only once committed", "[core]") {
    BinaryStateWriter memory(InMemory{"state"});
    addRecords(memory);
    CHECK_THROWS_AS(memory.takeBytes(), Error);
    memory.commit();
    CHECK(memory.takeBytes().size() == memory.bytes());
}
