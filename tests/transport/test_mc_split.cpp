// The photon Monte Carlo split over ranks (transport/mc_split.h), in one process: each rank's
// share is traced with a communicator that records what the rank would contribute, and a
// replay of the added contributions gives the merged run, which must equal one process's run
// bit for bit (tests/mpi/ does the same under mpirun).
#include <catch2/catch.hpp>

#include <cstring>

#include <nlohmann/json.hpp>

#include "mc_test_support.h"
#include "vpsim/transport/beam_convolution.h"
#include "vpsim/transport/mc_split.h"

using namespace vpsim;
using namespace vpsim::transport;

namespace {

/// Rank `rank` of `ranks`: sumIntegers records the rank's contribution, or (replaying) replaces
/// it by the sum of all ranks' contributions.
class RecordingRank final : public cluster::Communicator {
public:
    RecordingRank(int rank, int ranks, const std::vector<uint64_t>* sum = nullptr)
        : mRank(rank), mRanks(ranks), mSum(sum) {}
    int ranks() const override { return mRanks; }
    int rank() const override { return mRank; }
    std::string kind() const override { return "recording"; }
    void sumIntegers(std::vector<uint64_t>& values) override {
        contribution = values;
        if (mSum) values = *mSum;
    }
    std::vector<std::string> gatherBytes(const std::string& mine) override { return {mine}; }
    std::string broadcastBytes(const std::string& bytes) override { return bytes; }
    void abort(int) override {}
    std::vector<uint64_t> contribution;

private:
    int mRank, mRanks;
    const std::vector<uint64_t>* mSum;
};

McResult mergedOverRanks(const McSetup& setup, int ranks) {
    std::vector<uint64_t> sum;
    for (int r = 0; r < ranks; ++r) {
        RecordingRank rank(r, ranks);
        runPhotonMcSplit(setup, nullptr, rank);
        if (sum.empty()) sum.assign(rank.contribution.size(), 0);
        REQUIRE(rank.contribution.size() == sum.size());
        for (size_t i = 0; i < sum.size(); ++i) sum[i] += rank.contribution[i];
    }
    RecordingRank replay(0, ranks, &sum);
    return runPhotonMcSplit(setup, nullptr, replay);
}

bool sameBits(double a, double b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

void requireIdentical(const McResult& a, const McResult& b) {
    for (int k = 0; k < MC_BATCHES; ++k) {
        const BatchTally &x = a.batches[size_t(k)], &y = b.batches[size_t(k)];
        CHECK(x.photons == y.photons);
        CHECK(x.diffuse == y.diffuse);
        CHECK(x.absorbed == y.absorbed);
        CHECK(x.interactions == y.interactions);
        CHECK(x.absorbedWithin == y.absorbedWithin);
    }
    REQUIRE(a.controlBatches.size() == b.controlBatches.size());
    for (size_t j = 0; j < a.controlBatches.size(); ++j)
        CHECK(a.controlBatches[j].controls == b.controlBatches[j].controls);
    CHECK(a.absorbedRZ == b.absorbedRZ);
    CHECK(a.absorbedRZBatches == b.absorbedRZBatches);
    CHECK(a.absorbedGrid == b.absorbedGrid);
    CHECK(sameBits(a.diffuse().value, b.diffuse().value));
    CHECK(sameBits(a.diffuse().standardError, b.diffuse().standardError));
    CHECK(sameBits(a.absorbed().value, b.absorbed().value));
    CHECK(a.energyBalanced());
}

}  // namespace

TEST_CASE("photon shares cover the run once, in whole rounds of control batches",
          "[transport][mpi]") {
    for (uint64_t photons : {uint64_t(1), uint64_t(1000), uint64_t(5000), uint64_t(1u << 20)}) {
        for (int ranks : {1, 2, 3, 4, 9}) {
            uint64_t next = 0;
            for (int r = 0; r < ranks; ++r) {
                const PhotonShare s = photonShare(photons, r, ranks);
                CHECK(s.first == next);
                if (r + 1 < ranks) CHECK((s.first + s.count) % MC_CONTROL_BATCHES == 0);
                next = s.first + s.count;
            }
            CHECK(next == photons);
        }
    }
    const nlohmann::json split = photonSplitJson(5000, 2);
    CHECK(split["photon_ranges"] == nlohmann::json::parse("[[0, 2048], [2048, 5000]]"));
}

TEST_CASE("a run split over ranks equals one process's run bit for bit", "[transport][mpi]") {
    SECTION("collision estimator with control variates, Gaussian beam convolved, slab") {
        McSetup s = test::hgSetup(0.5, 20.0, 0.8, 1.4, 0.3, 5000, 7);
        s.beam = BeamShape::Gaussian;
        s.w0 = 0.06;
        s.bins = {0.2, 0.3, 20, 15};
        s.depths = {0.05, 0.1};
        s.firstPhoton = 123;
        REQUIRE(convolvesBeam(s));
        const McResult one = runPhotonMcCpu(s);
        REQUIRE(one.controlled());
        for (int ranks : {2, 3, 4}) requireIdentical(mergedOverRanks(s, ranks), one);
    }
    SECTION("implicit capture with bins per batch and a Cartesian grid; ranks without photons") {
        McSetup s = test::hgSetup(1.0, 10.0, 0.5, 1.0, 0.0, 1500, 3);
        s.estimator = Estimator::Implicit;
        s.binsPerBatch = true;
        s.bins = {0.2, 0.2, 10, 10};
        s.grid = {0.02, 8, 6};
        const McResult one = runPhotonMcCpu(s);
        requireIdentical(mergedOverRanks(s, 4), one);  // ranks 0 and 2 trace nothing
    }
}
