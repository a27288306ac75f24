// The cluster module in one process: launch detection, item distribution, and the collectives'
// single-process identities (tests/mpi/ runs the same calls under mpirun).
#include <catch2/catch.hpp>

#include <algorithm>
#include <set>

#include "vpsim/cluster/collectives.h"
#include "vpsim/core/error.h"

using namespace vpsim::cluster;

TEST_CASE("a process is launched by MPI only when a launcher's variable is set", "[cluster]") {
    LaunchEnvironment plain;
    CHECK_FALSE(plain.launched());
    CHECK(plain.worldSize() == 1);
    LaunchEnvironment ompi;
    ompi.ompiWorldSize = "4";
    CHECK(ompi.launched());
    CHECK(ompi.worldSize() == 4);
    LaunchEnvironment slurm;
    slurm.pmiSize = "3";
    CHECK(slurm.launched());
    CHECK(slurm.worldSize() == 3);
    LaunchEnvironment pmix;
    pmix.pmixRank = "0";
    CHECK(pmix.launched());
    CHECK(pmix.worldSize() == 1);
    // A plain run never starts MPI.
    const auto comm = startCommunicator(plain);
    CHECK(comm->ranks() == 1);
    CHECK(comm->kind() == "single process");
}

TEST_CASE("a build without MPI refuses a multi-process launch", "[cluster]") {
    LaunchEnvironment two;
    two.ompiWorldSize = "2";
    if (builtWithMpi())
        SUCCEED("built with MPI: tests/mpi/run_mpi_tests.sh covers the launch");
    else
        CHECK_THROWS_AS(startCommunicator(two), vpsim::InputError);
}

TEST_CASE("items are dealt round-robin: every index once, each rank's in order", "[cluster]") {
    for (int ranks : {1, 2, 3, 4, 7}) {
        for (size_t n : {size_t(0), size_t(1), size_t(5), size_t(12)}) {
            std::set<size_t> seen;
            for (int r = 0; r < ranks; ++r) {
                const std::vector<size_t> items = itemsOfRank(n, r, ranks);
                for (size_t k = 0; k < items.size(); ++k) {
                    CHECK(ownerOfItem(items[k], ranks) == r);
                    if (k > 0) CHECK(items[k] > items[k - 1]);
                    CHECK(seen.insert(items[k]).second);
                }
            }
            CHECK(seen.size() == n);
        }
    }
}

TEST_CASE("one process: the collectives are identities and runItems keeps index order",
          "[cluster]") {
    SingleProcess one;
    std::vector<uint64_t> values{1, 2, ~uint64_t(0)};
    one.sumIntegers(values);
    CHECK(values == std::vector<uint64_t>{1, 2, ~uint64_t(0)});
    CHECK(one.broadcastBytes("abc") == "abc");
    CHECK(one.gatherBytes("xyz") == std::vector<std::string>{"xyz"});
    const std::vector<double> sum = sumInRankOrder(one, {0.1, -2.5});
    CHECK(sum == std::vector<double>{0.1, -2.5});
    const std::vector<nlohmann::json> gathered = gatherJson(one, {{"a", 1}});
    REQUIRE(gathered.size() == 1);
    CHECK(gathered[0]["a"] == 1);
    // Results of different lengths (one empty, one with NUL bytes) come back whole, in order.
    const std::vector<std::string> results = runItems(one, 4, [](size_t i) {
        return i == 2 ? std::string() : std::string(i + 1, char('a' + i)) + std::string(1, '\0');
    });
    REQUIRE(results.size() == 4);
    CHECK(results[0] == std::string("a") + '\0');
    CHECK(results[1] == std::string("bb") + '\0');
    CHECK(results[2].empty());
    CHECK(results[3] == std::string("dddd") + '\0');
}

TEST_CASE("streamToRoot passes a rank's bytes to rank 0 whole, in pieces of at most a chunk",
          "[cluster]") {
    SingleProcess one;
    std::string bytes;
    for (int i = 0; i < 1000; ++i) bytes += char(i * 7 % 251);
    for (size_t chunk : {size_t(1), size_t(7), size_t(999), size_t(1000), size_t(4096)}) {
        std::string got;
        size_t pieces = 0, largest = 0;
        streamToRoot(
            one, 0, bytes.size(),
            [&](uint64_t offset, size_t count) { return bytes.substr(size_t(offset), count); },
            [&](const std::string& piece) {
                got += piece;
                ++pieces;
                largest = std::max(largest, piece.size());
            },
            chunk);
        CHECK(got == bytes);
        CHECK(pieces == (bytes.size() + chunk - 1) / chunk);
        CHECK(largest <= chunk);
    }
    // Nothing to pass: no piece; a short read is an error, not a shorter stream.
    streamToRoot(
        one, 0, 0, [](uint64_t, size_t) { return std::string("x"); },
        [](const std::string&) { FAIL("a piece of nothing"); });
    CHECK_THROWS_WITH(
        streamToRoot(
            one, 0, 10, [](uint64_t, size_t count) { return std::string(count - 1, 'x'); },
            [](const std::string&) {}, 4),
        Catch::Contains("read 3 of 4 bytes at 0"));
}
