#pragma once
// Subcommand registry of the vpsim CLI. Each tools/vpsim/cmd_*.cpp registers itself with a
// static CommandRegistration, so adding a command never touches main.cpp:
//
//   static vpsim::cli::CommandRegistration registerMie{"mie", [](CLI::App& app, const Globals& g) {
//       auto* cmd = app.add_subcommand("mie", "Lorenz-Mie scattering of one particle");
//       auto opts = std::make_shared<MieOptions>();   // options must outlive this function
//       cmd->add_option("--x", opts->x, "size parameter");
//       cmd->callback([opts, &g] { runMie(*opts, g); });
//   }};
//
// Callbacks throw vpsim::Error (InputError, GpuError, ResourceError) for anything the user must
// fix; main() prints one line "vpsim: error: ..." and exits non-zero. Results go to stdout
// (JSON with --json), messages and progress to stderr.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "vpsim/cluster/communicator.h"
#include "vpsim/core/run_context.h"
#include "vpsim/gpu/context.h"

namespace vpsim::cli {

/// Options shared by every subcommand (parsed before the callbacks run).
struct Globals {
    std::string backend = "auto";        ///< auto | vulkan | cpu
    std::string device;                  ///< Vulkan device index or name part
    bool validation = false;             ///< run under VK_LAYER_KHRONOS_validation
    std::vector<std::string> overrides;  ///< --set key.path=value for config files
    bool quiet = false;

    std::string cacheDirectory;  ///< beam-kernel cache (VPSIM_CACHE_DIR, ~/.cache/vpsim)
    /// Memory budget in bytes (VPSIM_MEMORY_LIMIT); 0: the library's default (RunContext).
    uint64_t memoryLimit = 0;

    /// Defaults from the environment (the library reads none): VPSIM_BACKEND, VPSIM_DEVICE,
    /// VPSIM_VALIDATION=1, VPSIM_LOG=error|warn|info|debug, VPSIM_CACHE_DIR (else
    /// $XDG_CACHE_HOME/vpsim, else ~/.cache/vpsim), VPSIM_MEMORY_LIMIT (5G, 512M, bytes; unset or
    /// empty: the default). Options given on the command line win.
    /// @throw InputError naming VPSIM_MEMORY_LIMIT when its value is malformed
    void readEnvironment();

    /// What runContext() holds without opening the Vulkan context: the cache directory and the
    /// memory limit (for estimates and memory checks).
    RunContext hostContext() const;

    /// The Vulkan context for --backend/--device, or nullptr for the CPU path (see
    /// gpu::contextForBackend). Created once on first use.
    std::shared_ptr<gpu::Context> gpu() const;

    /// What the library's runs need: the context, the cache directory; --backend vulkan also
    /// puts the exposure shaders on a CPU driver (lavapipe), where they are slower.
    RunContext runContext() const;

    /// This process's ranks: MPI when mpirun/srun started it (OMPI_COMM_WORLD_SIZE, PMI_SIZE,
    /// PMIX_RANK), else one process; started on first use (`vpsim run`, `vpsim batch`), so
    /// other commands never initialise MPI.
    std::shared_ptr<cluster::Communicator> communicator() const;
    /// After an error on this rank: ends the other ranks too, which would otherwise wait for it
    /// in a collective call (nothing in one process).
    void abortOtherRanks() const;
    /// The exit status when the command returns normally (`vpsim batch` with a failed job).
    mutable int exitStatus = 0;

private:
    mutable std::shared_ptr<cluster::Communicator> mCommunicator;
    mutable std::shared_ptr<gpu::Context> mGpu;
    mutable bool mGpuResolved = false;
};

using CommandSetup = std::function<void(CLI::App& app, const Globals& globals)>;

struct CommandRegistration {
    CommandRegistration(const std::string& name, CommandSetup setup);
};

/// All registered setups, in registration order.
std::vector<std::pair<std::string, CommandSetup>>& commandRegistry();

/// A command's option name for a library argument's key: "r_max" -> "--r-max" (the name
/// transport::mcSetup and kernel::kernelOptions give it in messages).
std::string optionName(const std::string& key);

/// Prints JSON to stdout with 2-space indentation.
void printJson(const nlohmann::json& value);

/// Prints registered components (pipeline::registryJson) for people: each name and description,
/// then each key as `section.key  default  (dimension)  doc`.
void printComponents(const nlohmann::json& list, const std::string& section);

}  // namespace vpsim::cli
