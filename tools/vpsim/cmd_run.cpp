// `vpsim run JOB.json --out DIR [--plan FILE]`: the main job (material -> kernel -> slice ->
// plan -> expose -> cure -> validate) with a report, grids, the cured mesh and pictures in DIR;
// `vpsim expose` is the same command, named for runs that start from a saved plan. Under
// mpirun/srun the ranks share the beam kernel's Monte Carlo and rank 0 writes DIR.
#include <cstdlib>
#include <iostream>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "vpsim/core/error.h"
#include "vpsim/pipeline/cluster_run.h"
#include "vpsim/pipeline/estimate.h"
#include "vpsim/pipeline/run_job.h"

namespace {

struct RunOptions {
    std::string job, out = "out", plan;
    bool json = false, dryRun = false, resume = false;
};

void runCommand(const RunOptions& options, const vpsim::cli::Globals& globals) {
    using namespace vpsim;
    const pipeline::Builtins builtins = pipeline::makeBuiltins();
    const pipeline::Job job = pipeline::loadJob(options.job, builtins, globals.overrides);
    // Under mpirun/srun every rank computes its share of the beam kernel's photons and rank 0
    // the rest (pipeline/cluster_run.h); a plain run is one process.
    const std::shared_ptr<cluster::Communicator> comm = globals.communicator();
    if (options.dryRun) {  // the estimate only: nothing computed, nothing written
        if (!comm->isRoot()) return;
        const pipeline::JobEstimate estimate = pipeline::fitEstimate(
            job, globals.hostContext(), false, !options.plan.empty(), globals.backend != "cpu");
        // What `vpsim run` would do with this estimate: run, or refuse (memory or disk) and why.
        std::string verdict = "runs within the memory budget and the free disk";
        try {
            pipeline::checkEstimate(estimate, globals.hostContext());
            pipeline::checkDisk(estimate, options.out);
        } catch (const ResourceError& refused) {
            verdict = std::string("refused: ") + refused.what();
        }
        if (options.json) {
            nlohmann::json out = estimate.toJson(globals.hostContext());
            out["verdict"] = verdict;
            return cli::printJson(out);
        }
        std::cout << estimate.table(globals.hostContext()) << "verdict: " << verdict << "\n";
        return;
    }
    pipeline::RunOptions run;
    run.planFile = options.plan;
    run.resume = options.resume;
    // A test hook (tests/mpi/run_mpi_tests.sh): stop once this many tiles are checkpointed
    // (over MPI ranks: after the first merged round that reaches it).
    if (const char* stop = std::getenv("VPSIM_STOP_AFTER_TILES")) {
        try {
            run.stopAfterTiles = std::stoi(stop);
        } catch (const std::exception&) {
            throw InputError("expected a number of tiles", "VPSIM_STOP_AFTER_TILES");
        }
    }
    RunContext context = globals.runContext();
    context.cluster = comm;
    if (!comm->isRoot()) return pipeline::runJobOnWorkerRank(job, context);
    const report::JobResult r = pipeline::runJob(job, options.out, context, run);
    if (options.json) {
        cli::printJson(report::toJson(r));
        return;
    }
    const validate::SurfaceDeviation& dev = r.validation.deviation;
    std::cout << "vpsim run " << job.name << " -> " << options.out << "/index.html\n"
              << "  volume IoU                     " << r.validation.slices.iou << "\n"
              << "  surface deviation (mm)         mean " << dev.mean << ", rms " << dev.rms
              << ", p95 " << dev.p95 << ", max " << dev.max << "\n"
              << "  over-cure below down-facing    "
              << r.validation.slices.overcureBelowDownFacingMedian << " mm\n";
}

void addRun(CLI::App& app, const vpsim::cli::Globals& globals, const std::string& name,
            const std::string& description) {
    auto* command = app.add_subcommand(name, description);
    auto options = std::make_shared<RunOptions>();
    command->add_option("job", options->job, "job file (JSON), e.g. examples/default.json")
        ->required();
    command->add_option("--out", options->out,
                        "output directory (report.json, index.html, .vdb, pictures)");
    command->add_option("--plan", options->plan,
                        "expose this saved or edited plan.json instead of planning");
    command->add_flag("--json", options->json, "print the report (or the estimate) as JSON");
    command->add_flag("--resume", options->resume,
                      "continue after the last tile of the checkpoint in --out (a pre-empted "
                      "tiled run, on any number of MPI ranks), exposing its plan.json; without "
                      "it a run starts over");
    command->add_flag("--dry-run", options->dryRun,
                      "print the job's memory, file and time estimate; compute and write nothing");
    command->callback([options, &globals] { runCommand(*options, globals); });
}

vpsim::cli::CommandRegistration registerRun{
    "run", [](CLI::App& app, const vpsim::cli::Globals& globals) {
        addRun(app, globals, "run", "simulate a print and compare the cured part with the model");
    }};

vpsim::cli::CommandRegistration registerExpose{
    "expose", [](CLI::App& app, const vpsim::cli::Globals& globals) {
        addRun(app, globals, "expose",
               "expose, cure and validate a plan (the same as run; use with --plan FILE)");
    }};

}  // namespace
