// `vpsim run JOB.json --out DIR`: the main job (material -> kernel -> slice -> plan -> expose ->
// cure -> validate) with a report, grids, the cured mesh and pictures in DIR.
#include <iostream>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "vpsim/report/run_job.h"

namespace {

struct RunOptions {
    std::string job, out = "out";
    bool json = false;
};

void runCommand(const RunOptions& options, const vpsim::cli::Globals& globals) {
    vpsim::report::Job job = vpsim::report::loadJob(options.job, globals.overrides);
    // --backend vulkan also puts the exposure on a CPU driver (lavapipe), where it is slower.
    nlohmann::json report =
        vpsim::report::runJob(job, options.out, globals.gpu(), globals.backend == "vulkan");
    if (options.json) {
        vpsim::cli::printJson(report);
        return;
    }
    const auto& dev = report["surface_deviation_mm"];
    std::cout << "vpsim run " << job.name << " -> " << options.out << "/index.html\n"
              << "  volume IoU                     " << report["iou"].get<double>() << "\n"
              << "  surface deviation (mm)         mean " << dev["mean"].get<double>() << ", rms "
              << dev["rms"].get<double>() << ", p95 " << dev["p95"].get<double>() << ", max "
              << dev["max"].get<double>() << "\n"
              << "  over-cure below down-facing    "
              << report["overcure_below_downfacing_mm"].get<double>() << " mm\n";
}

vpsim::cli::CommandRegistration registerRun{
    "run", [](CLI::App& app, const vpsim::cli::Globals& globals) {
        auto* command =
            app.add_subcommand("run", "simulate a print and compare the cured part with the model");
        auto options = std::make_shared<RunOptions>();
        command->add_option("job", options->job, "job file (JSON), e.g. examples/default.json")
            ->required();
        command->add_option("--out", options->out,
                            "output directory (report.json, index.html, .vdb, pictures)");
        command->add_flag("--json", options->json, "print the report as JSON");
        command->callback([options, &globals] { runCommand(*options, globals); });
    }};

}  // namespace
