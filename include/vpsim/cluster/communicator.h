#pragma once
/// @file
/// The processes of one run (MPI ranks), behind an interface that is one process doing
/// everything when vpsim was built without MPI or not started by mpirun/srun. Every call is
/// collective: all ranks make the same calls in the same order. Reductions are exact (integer
/// sums, modulo 2^64) or in a fixed order (doubles summed in rank order), so a result does not
/// depend on the number of ranks or on who finished first.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace vpsim::cluster {

class Communicator {
public:
    virtual ~Communicator() = default;
    virtual int ranks() const = 0;
    virtual int rank() const = 0;
    /// "mpi" or "single process".
    virtual std::string kind() const = 0;
    /// Element-wise sum over the ranks (integers: exact, wrapping modulo 2^64, so signed values
    /// stored as two's complement add too); every rank receives the sum. Sizes must agree.
    virtual void sumIntegers(std::vector<uint64_t>& values) = 0;
    /// Each rank's bytes, on rank 0, in rank order; empty on the other ranks.
    virtual std::vector<std::string> gatherBytes(const std::string& mine) = 0;
    /// Rank 0's bytes on every rank (`bytes` is read on rank 0 only).
    virtual std::string broadcastBytes(const std::string& bytes) = 0;
    /// Ends every rank's process with `code` (after an error on one rank, so that the others do
    /// not wait for it forever). The single process does nothing: its caller exits as usual.
    virtual void abort(int code) = 0;

    bool isRoot() const { return rank() == 0; }
};

/// One process, every collective the identity.
class SingleProcess final : public Communicator {
public:
    int ranks() const override { return 1; }
    int rank() const override { return 0; }
    std::string kind() const override { return "single process"; }
    void sumIntegers(std::vector<uint64_t>&) override {}
    std::vector<std::string> gatherBytes(const std::string& mine) override { return {mine}; }
    std::string broadcastBytes(const std::string& bytes) override { return bytes; }
    void abort(int) override {}
};

/// What tells a process it was started by a launcher: Open MPI's mpirun sets
/// OMPI_COMM_WORLD_SIZE, Slurm's srun and Hydra set PMI_SIZE, PMIx launchers PMIX_RANK. The
/// library reads no environment: the caller passes the variables' values (null when unset).
struct LaunchEnvironment {
    const char* ompiWorldSize = nullptr;
    const char* pmiSize = nullptr;
    const char* pmixRank = nullptr;
    /// Processes the launcher started (OMPI_COMM_WORLD_SIZE or PMI_SIZE), 1 when unknown.
    int worldSize() const;
    bool launched() const;
};

/// Whether this build can use MPI (VPSIM_WITH_MPI: Open MPI was found at build time).
bool builtWithMpi();

/// The communicator of this process: MPI (initialised here, finalised when the last reference
/// goes) when the environment says a launcher started it, else a SingleProcess. A plain run
/// never initialises MPI.
/// @throw InputError when launched with more than one process by a build without MPI (each
///        process would otherwise run the whole job and write the same files)
std::shared_ptr<Communicator> startCommunicator(const LaunchEnvironment& environment);

}  // namespace vpsim::cluster
