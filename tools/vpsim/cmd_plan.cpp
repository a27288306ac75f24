// `vpsim plan JOB.json --out DIR`: the stages up to the plan (part, kernel, slices, planner),
// writing plan.json for `vpsim run JOB --plan DIR/plan.json`; `vpsim plan --list` names the
// registered planners with their keys.
#include <iostream>

#include "commands.h"
#include "vpsim/pipeline/builtins.h"
#include "vpsim/pipeline/estimate.h"
#include "vpsim/pipeline/run_job.h"

namespace {

struct PlanOptions {
    std::string job, out = "out";
    bool list = false, json = false, dryRun = false;
};

void planCommand(const PlanOptions& options, const vpsim::cli::Globals& globals) {
    using namespace vpsim;
    const pipeline::Builtins builtins = pipeline::makeBuiltins();
    if (options.list) {
        const nlohmann::json list = pipeline::registryJson(builtins.planners);
        if (options.json) return cli::printJson(list);
        cli::printComponents(list, "plan");
        return;
    }
    if (options.job.empty()) throw InputError("vpsim plan needs a job file (or --list)");
    const pipeline::Job job = pipeline::loadJob(options.job, builtins, globals.overrides);
    if (options.dryRun) {  // the estimate only: nothing computed, nothing written
        const pipeline::JobEstimate estimate =
            pipeline::estimateJob(job, true, false, globals.backend != "cpu");
        if (options.json) return cli::printJson(estimate.toJson(globals.hostContext()));
        std::cout << estimate.table(globals.hostContext());
        return;
    }
    const pipeline::PlanResult plan = pipeline::planJob(job, options.out, globals.runContext());
    nlohmann::json out{{"plan", options.out + "/plan.json"},
                       {"strategy", job.strategy},
                       {"layers", plan.plan.layers.size()},
                       {"energy_mJ", plan.plan.totalEnergy()},
                       {"planner", plan.summary}};
    if (options.json) return cli::printJson(out);
    std::cout << "vpsim plan " << job.name << " (" << job.strategy << ") -> " << options.out
              << "/plan.json: " << plan.plan.layers.size() << " layers, " << plan.plan.totalEnergy()
              << " mJ\n";
}

vpsim::cli::CommandRegistration registerPlan{
    "plan", [](CLI::App& app, const vpsim::cli::Globals& globals) {
        auto* command = app.add_subcommand(
            "plan", "plan a job (part, kernel, slices, planner) and write plan.json");
        auto options = std::make_shared<PlanOptions>();
        command->add_option("job", options->job, "job file (JSON)");
        command->add_option("--out", options->out, "output directory");
        command->add_flag("--list", options->list, "list the planners and their keys");
        command->add_flag("--json", options->json, "print JSON");
        command->add_flag("--dry-run", options->dryRun,
                          "print the estimate of the stages up to the plan; compute nothing");
        command->callback([options, &globals] { planCommand(*options, globals); });
    }};

}  // namespace
