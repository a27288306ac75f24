// MPI_COMM_WORLD behind the Communicator interface. Only the thread that started MPI calls it
// (MPI_THREAD_FUNNELED): TBB's workers never communicate.
#ifdef VPSIM_WITH_MPI
#include "mpi_communicator.h"

#include <mpi.h>

#include <climits>

#include "vpsim/core/error.h"

namespace vpsim::cluster {
namespace {

void check(int status, const char* call) {
    if (status != MPI_SUCCESS) throw Error(std::string("MPI: ") + call + " failed");
}

int countOf(size_t bytes) {
    if (bytes > size_t(INT_MAX)) throw ResourceError("MPI: message over 2 GiB");
    return int(bytes);
}

class MpiCommunicator final : public Communicator {
public:
    MpiCommunicator() {
        int provided = 0;
        check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
        MPI_Comm_size(MPI_COMM_WORLD, &mRanks);
        MPI_Comm_rank(MPI_COMM_WORLD, &mRank);
    }
    ~MpiCommunicator() override { MPI_Finalize(); }

    int ranks() const override { return mRanks; }
    int rank() const override { return mRank; }
    std::string kind() const override { return "mpi"; }

    void sumIntegers(std::vector<uint64_t>& values) override {
        // Chunks of at most INT_MAX elements (MPI counts are int).
        for (size_t at = 0; at < values.size(); at += size_t(INT_MAX)) {
            const int n = int(std::min(values.size() - at, size_t(INT_MAX)));
            check(MPI_Allreduce(MPI_IN_PLACE, values.data() + at, n, MPI_UINT64_T, MPI_SUM,
                                MPI_COMM_WORLD),
                  "MPI_Allreduce");
        }
    }

    std::vector<std::string> gatherBytes(const std::string& mine) override {
        const int size = countOf(mine.size());
        std::vector<int> sizes(size_t(mRanks), 0), offsets(size_t(mRanks), 0);
        check(MPI_Gather(&size, 1, MPI_INT, sizes.data(), 1, MPI_INT, 0, MPI_COMM_WORLD),
              "MPI_Gather");
        size_t total = 0;
        for (int r = 0; r < mRanks && mRank == 0; ++r) {
            offsets[size_t(r)] = countOf(total);
            total += size_t(sizes[size_t(r)]);
        }
        std::string all(mRank == 0 ? countOf(total) : 0, '\0');
        check(MPI_Gatherv(mine.data(), size, MPI_CHAR, all.data(), sizes.data(), offsets.data(),
                          MPI_CHAR, 0, MPI_COMM_WORLD),
              "MPI_Gatherv");
        std::vector<std::string> out;
        if (mRank != 0) return out;
        for (int r = 0; r < mRanks; ++r)
            out.push_back(all.substr(size_t(offsets[size_t(r)]), size_t(sizes[size_t(r)])));
        return out;
    }

    std::string broadcastBytes(const std::string& bytes) override {
        int size = mRank == 0 ? countOf(bytes.size()) : 0;
        check(MPI_Bcast(&size, 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Bcast");
        std::string out = mRank == 0 ? bytes : std::string(size_t(size), '\0');
        check(MPI_Bcast(out.data(), size, MPI_CHAR, 0, MPI_COMM_WORLD), "MPI_Bcast");
        return out;
    }

    void abort(int code) override { MPI_Abort(MPI_COMM_WORLD, code); }

private:
    int mRanks = 1, mRank = 0;
};

}  // namespace

std::shared_ptr<Communicator> startMpi() {
    return std::make_shared<MpiCommunicator>();
}

}  // namespace vpsim::cluster
#endif
