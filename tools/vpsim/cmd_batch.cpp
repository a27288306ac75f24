// `vpsim batch JOB... --out DIR` or `vpsim batch --sweep FILE --out DIR`: runs jobs one after
// another in one process, each into DIR/<name>, and writes DIR/batch.json (each job's status
// and headline figures). A failed job does not stop the others; the exit status is non-zero when
// any failed. Under mpirun/srun the jobs are spread over the ranks round-robin (job i on rank
// i % ranks), each rank runs and writes its own jobs as one process, and rank 0 writes
// batch.json.
#include <chrono>
#include <iostream>

#include "batch_entries.h"
#include "commands.h"
#include "vpsim/cluster/collectives.h"
#include "vpsim/core/io.h"
#include "vpsim/core/log.h"
#include "vpsim/core/progress.h"
#include "vpsim/pipeline/builtins.h"
#include "vpsim/pipeline/run_job.h"

namespace {

struct BatchOptions {
    std::vector<std::string> jobs;
    std::string sweep, out = "batch";
    bool json = false;
};

/// The figures of report.json that batch.json repeats for each job.
nlohmann::json headline(const nlohmann::json& report) {
    nlohmann::json out = nlohmann::json::object();
    for (const char* key : {"iou", "surface_deviation_mm", "overcure_below_downfacing_mm",
                            "cured_volume_mm3", "build_time_s"})
        if (report.contains(key)) out[key] = report[key];
    out["energy_mJ"] = report["plan"]["energy_mJ"];
    out["layers"] = report["plan"]["layers"];
    if (report.contains("kernel"))
        out["kernel"] = {{"We3D_um", report["kernel"]["We3D_um"]},
                         {"De3D_um", report["kernel"]["De3D_um"]}};
    return out;
}

/// Runs one job into `dir` as one process; a failure is reported, not thrown.
nlohmann::json runEntry(const vpsim::cli::BatchEntry& entry, const std::string& dir,
                        const vpsim::RunContext& context, int rank) {
    using namespace vpsim;
    nlohmann::json status = {{"name", entry.name},
                             {"job_file", entry.jobFile},
                             {"overrides", entry.overrides},
                             {"out", dir},
                             {"rank", rank}};
    const auto start = std::chrono::steady_clock::now();
    try {
        const pipeline::Builtins builtins = pipeline::makeBuiltins();
        const pipeline::Job job = pipeline::loadJob(entry.jobFile, builtins, entry.overrides);
        const report::JobResult result = pipeline::runJob(job, dir, context);
        status["status"] = "ok";
        status["figures"] = headline(report::toJson(result));
    } catch (const std::exception& e) {
        status["status"] = "failed";
        status["error"] = e.what();
        logWarn("batch: job " + entry.name + " failed: " + e.what());
    }
    status["seconds"] =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return status;
}

void batchCommand(const BatchOptions& options, const vpsim::cli::Globals& globals) {
    using namespace vpsim;
    if (options.jobs.empty() == options.sweep.empty())
        throw InputError("give job files or --sweep FILE (one of the two)", "", "batch");
    const std::vector<cli::BatchEntry> entries =
        options.sweep.empty() ? cli::entriesOfJobs(options.jobs, globals.overrides)
                              : cli::entriesOfSweep(options.sweep, globals.overrides);
    const std::shared_ptr<cluster::Communicator> comm = globals.communicator();
    RunContext context = globals.runContext();
    context.cluster = nullptr;  // each job runs whole on the rank that owns it
    createDirectories(options.out);

    const size_t mine = cluster::itemsOfRank(entries.size(), comm->rank(), comm->ranks()).size();
    Progress progress("batch jobs", mine);
    std::vector<std::string> results = cluster::runItems(*comm, entries.size(), [&](size_t i) {
        logInfo("batch: job " + std::to_string(i + 1) + "/" + std::to_string(entries.size()) + " " +
                entries[i].name + " (rank " + std::to_string(comm->rank()) + ")");
        const nlohmann::json status =
            runEntry(entries[i], options.out + "/" + entries[i].name, context, comm->rank());
        progress.advance();
        return status.dump();
    });
    progress.finish();
    if (!comm->isRoot()) return;

    nlohmann::json jobs = nlohmann::json::array();
    std::vector<std::string> failed;
    for (const std::string& text : results) {
        jobs.push_back(nlohmann::json::parse(text));
        if (jobs.back()["status"] != "ok") failed.push_back(jobs.back()["name"]);
    }
    const nlohmann::json summary = {
        {"jobs", jobs},
        {"succeeded", entries.size() - failed.size()},
        {"failed", failed.size()},
        {"mpi",
         {{"ranks", comm->ranks()}, {"split", "jobs round-robin: job i on rank i % ranks"}}}};
    writeFileAtomic(options.out + "/batch.json", summary.dump(2));
    if (options.json) {
        cli::printJson(summary);
    } else {
        for (const nlohmann::json& job : jobs) {
            std::cout << job["name"].get<std::string>() << "  " << job["status"].get<std::string>();
            if (job["status"] == "ok") std::cout << "  IoU " << job["figures"]["iou"];
            std::cout << "\n";
        }
    }
    if (!failed.empty()) {
        std::string names;
        for (const std::string& n : failed) names += (names.empty() ? "" : ", ") + n;
        std::cerr << "vpsim: error: " << failed.size() << " of " << entries.size()
                  << " batch jobs failed (" << names << "); see " << options.out << "/batch.json\n";
        globals.exitStatus = 1;
    }
}

vpsim::cli::CommandRegistration registerBatch{
    "batch", [](CLI::App& app, const vpsim::cli::Globals& globals) {
        auto* command = app.add_subcommand(
            "batch",
            "run several jobs (or a sweep of one job) into DIR/<name>, with DIR/batch.json");
        auto options = std::make_shared<BatchOptions>();
        command->add_option("jobs", options->jobs, "job files (JSON); each writes DIR/<file stem>");
        command->add_option("--sweep", options->sweep,
                            "sweep file: {\"job\": FILE, \"runs\": [{\"name\": N, \"set\": "
                            "[\"key=value\", ...]}, ...]}");
        command->add_option("--out", options->out, "output directory (one folder per job)");
        command->add_flag("--json", options->json, "print batch.json");
        command->callback([options, &globals] { batchCommand(*options, globals); });
    }};

}  // namespace
