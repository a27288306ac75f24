// Run under `mpirun -np N` (tests/mpi/run_mpi_tests.sh): the collectives across real ranks, the
// tile helper (cluster::runItems) and the photon Monte Carlo split over the ranks against one
// process's run of the same setup, bit for bit. Prints one line per failure on rank 0 and exits
// non-zero there.
#include <cstdlib>
#include <cstring>
#include <iostream>

#include "vpsim/cluster/collectives.h"
#include "vpsim/transport/mc_split.h"

using namespace vpsim;

namespace {

int failures = 0;
void expect(bool ok, const std::string& what) {
    if (!ok) {
        ++failures;
        std::cerr << "mpi_check: FAILED: " << what << "\n";
    }
}

void checkCollectives(cluster::Communicator& comm) {
    const int r = comm.rank(), n = comm.ranks();
    std::vector<uint64_t> sum{uint64_t(r + 1), ~uint64_t(0)};  // the second wraps modulo 2^64
    comm.sumIntegers(sum);
    expect(sum[0] == uint64_t(n) * (n + 1) / 2 && sum[1] == uint64_t(0) - uint64_t(n),
           "sumIntegers");
    const std::vector<std::string> gathered =
        comm.gatherBytes(std::string(size_t(r), char('a' + r)));
    if (comm.isRoot()) {
        expect(int(gathered.size()) == n, "gatherBytes: one entry per rank");
        for (int k = 0; k < int(gathered.size()); ++k)
            expect(gathered[size_t(k)] == std::string(size_t(k), char('a' + k)),
                   "gatherBytes: rank order");
    } else {
        expect(gathered.empty(), "gatherBytes: empty off rank 0");
    }
    expect(comm.broadcastBytes(comm.isRoot() ? "from rank 0" : "") == "from rank 0",
           "broadcastBytes");
    // Doubles in rank order: 0.1 + 0.2 + 0.3 + ... added left to right, the same on every rank.
    const std::vector<double> total = cluster::sumInRankOrder(comm, {0.1 * (r + 1)});
    double expected = 0.0;
    for (int k = 0; k < n; ++k) expected += 0.1 * (k + 1);
    expect(std::memcmp(&total[0], &expected, sizeof expected) == 0, "sumInRankOrder");
    // The tile helper: 11 items, each result naming its item and the rank that made it.
    const std::vector<std::string> items = cluster::runItems(
        comm, 11, [&](size_t i) { return std::to_string(i) + "@" + std::to_string(comm.rank()); });
    if (comm.isRoot())
        for (size_t i = 0; i < 11; ++i)
            expect(items.size() == 11 && items[i] == std::to_string(i) + "@" +
                                                         std::to_string(cluster::ownerOfItem(i, n)),
                   "runItems: item " + std::to_string(i) + " in index order");
    // Each rank's stream (of a length its own, the last rank's none) passed to rank 0 in pieces
    // of 7 bytes, and one piece larger than the stream.
    for (size_t chunk : {size_t(7), size_t(1000)}) {
        for (int owner = 0; owner < n; ++owner) {
            const uint64_t length = owner == n - 1 ? 0 : uint64_t(50 + 13 * owner);
            std::string sent;
            for (uint64_t k = 0; k < length; ++k) sent += char('A' + (owner + k) % 26);
            std::string got;
            cluster::streamToRoot(
                comm, owner, length,
                [&](uint64_t offset, size_t count) {
                    expect(comm.rank() == owner, "streamToRoot: read on the owner only");
                    return sent.substr(size_t(offset), count);
                },
                [&](const std::string& piece) {
                    expect(comm.isRoot() && piece.size() <= chunk,
                           "streamToRoot: pieces of at most a chunk, on rank 0 only");
                    got += piece;
                },
                chunk);
            if (comm.isRoot())
                expect(got == sent, "streamToRoot: rank " + std::to_string(owner) +
                                        "'s bytes whole and in order");
        }
    }
}

bool sameTallies(const transport::McResult& a, const transport::McResult& b) {
    bool same = a.absorbedRZ == b.absorbedRZ && a.absorbedRZBatches == b.absorbedRZBatches &&
                a.absorbedGrid == b.absorbedGrid &&
                a.controlBatches.size() == b.controlBatches.size();
    for (int k = 0; k < transport::MC_BATCHES; ++k) {
        const auto &x = a.batches[size_t(k)], &y = b.batches[size_t(k)];
        same = same && x.photons == y.photons && x.diffuse == y.diffuse &&
               x.absorbed == y.absorbed && x.interactions == y.interactions;
    }
    for (size_t j = 0; same && j < a.controlBatches.size(); ++j)
        same = a.controlBatches[j].controls == b.controlBatches[j].controls;
    const double da = a.diffuse().value, db = b.diffuse().value;
    return same && std::memcmp(&da, &db, sizeof da) == 0;
}

void checkMonteCarlo(cluster::Communicator& comm) {
    transport::McSetup s;
    s.optics.mua = 0.5;
    s.optics.mus = 20.0;
    s.optics.g = 0.8;
    s.optics.refractiveIndex = 1.4;
    s.beam = transport::BeamShape::Gaussian;
    s.w0 = 0.06;
    s.bins = {0.2, 0.3, 20, 15};
    s.depths = {0.05};
    s.photons = 3000;  // with 4 ranks, one traces nothing
    s.firstPhoton = 77;
    s.seed = 5;
    for (transport::Estimator e : {transport::Estimator::Collision, transport::Estimator::Track}) {
        s.estimator = e;
        const transport::McResult split = transport::runPhotonMcSplit(s, nullptr, comm);
        // Every rank holds the merged result; rank 0 compares it with one process's run.
        std::vector<uint64_t> agree{
            comm.isRoot() ? uint64_t(sameTallies(split, transport::runPhotonMcCpu(s))) : 0};
        comm.sumIntegers(agree);
        expect(agree[0] == 1, std::string("split Monte Carlo = one process (") +
                                  transport::estimatorName(e) + ")");
    }
}

}  // namespace

int main() {
    cluster::LaunchEnvironment launch;
    launch.ompiWorldSize = std::getenv("OMPI_COMM_WORLD_SIZE");
    launch.pmiSize = std::getenv("PMI_SIZE");
    launch.pmixRank = std::getenv("PMIX_RANK");
    bool root = true;
    {
        const std::shared_ptr<cluster::Communicator> comm = cluster::startCommunicator(launch);
        root = comm->isRoot();
        if (comm->ranks() != launch.worldSize()) {
            std::cerr << "mpi_check: FAILED: " << comm->ranks() << " ranks, the launcher started "
                      << launch.worldSize() << "\n";
            return 1;
        }
        checkCollectives(*comm);
        checkMonteCarlo(*comm);
        std::vector<uint64_t> all{uint64_t(failures)};
        comm->sumIntegers(all);
        failures = int(all[0]);
        if (root)
            std::cout << "mpi_check: " << comm->ranks() << " ranks, " << failures << " failures\n";
    }  // MPI_Finalize
    return root && failures > 0 ? 1 : 0;
}
