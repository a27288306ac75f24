// `vpsim run` and `vpsim batch` over MPI ranks (issue 22 item 3) against one plain process, all
// measured in this run: the small laser job with a Monte Carlo kernel of many photons (the work
// the ranks split) under `mpirun --oversubscribe --bind-to none -np 1, 2, 4`, and a batch of 4 jobs
// over the same ranks, and the pipeline's block job in x-y tiles over the same ranks (with and
// without the figures and the 3D view). Prints JSON:
// wall seconds and the kernel stage's seconds per rank count, the speed-up against 1 rank, whether
// every report.json's figures equal the plain process's, the machine's cores and load (ranks share
// the cores: beyond the core count nothing is gained).
// Usage: bench_mpi [--photons N (default 400000)]
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "vpsim/cluster/communicator.h"

namespace {

namespace fs = std::filesystem;

/// report.json without what differs between runs of one job (timings, paths, the split).
nlohmann::json figures(const fs::path& report) {
    std::ifstream in(report);
    nlohmann::json r = nlohmann::json::parse(in, nullptr, false);
    if (r.is_discarded()) return nullptr;
    for (const char* key : {"mpi", "stage_seconds", "files", "job"}) r.erase(key);
    if (r.contains("kernel")) r["kernel"].erase("from_cache");
    nlohmann::json flat = r.flatten();
    for (auto it = flat.begin(); it != flat.end();)
        it = it.key().find("seconds") != std::string::npos ? flat.erase(it) : std::next(it);
    return flat;
}

double kernelSeconds(const fs::path& report) {
    std::ifstream in(report);
    const nlohmann::json r = nlohmann::json::parse(in, nullptr, false);
    if (r.is_discarded() || !r.contains("stage_seconds")) return -1;
    for (const auto& stage : r["stage_seconds"].items())
        if (stage.key() == "kernel") return stage.value().get<double>();
    return -1;
}

/// Wall seconds of a shell command; -1 when it fails.
double timed(const std::string& command) {
    const auto start = std::chrono::steady_clock::now();
    const int status = std::system(command.c_str());
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return status == 0 ? seconds : -1;
}

double loadAverage() {
    double load[1] = {0};
    return getloadavg(load, 1) == 1 ? load[0] : -1;
}

/// The files of a run's pictures and 3D view (png, svg, js), by name, with their bytes.
std::map<std::string, std::string> pictureFiles(const fs::path& dir) {
    std::map<std::string, std::string> files;
    std::error_code error;
    for (const auto& entry : fs::directory_iterator(dir, error)) {
        const std::string extension = entry.path().extension().string();
        if (extension != ".png" && extension != ".svg" && extension != ".js") continue;
        std::ifstream in(entry.path(), std::ios::binary);
        files[entry.path().filename().string()] =
            std::string(std::istreambuf_iterator<char>(in), {});
    }
    return files;
}

/// The pipeline's block job (benchmarks/jobs/block-10mm.json at 5 x 5 x 1 mm, 2.6e7 voxels) in
/// 1 mm x-y tiles with `outputs` (simulation.outputs), in one plain process and over 1, 2 and 4
/// ranks (the tiles dealt round-robin, merged on rank 0): wall and expose-stage seconds, and
/// whether report.json's figures, cured.stl and the pictures equal the plain process's.
nlohmann::json tiledRuns(const fs::path& work, const std::string& vpsim, const std::string& job,
                         const std::string& outputs) {
    const std::string set =
        " --set part.size=5mm --set part.height=1mm --set simulation.tile=1mm"
        " --set 'simulation.outputs=" +
        outputs + "'";
    const std::string tag = outputs.find("figures") != std::string::npos ? "pictures-" : "";
    auto stage = [](const fs::path& report, const std::string& name) {
        std::ifstream in(report);
        const nlohmann::json r = nlohmann::json::parse(in, nullptr, false);
        return r.is_discarded() ? -1.0 : r["stage_seconds"].value(name, -1.0);
    };
    auto file = [](const fs::path& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    nlohmann::json out = {{"job", "benchmarks/jobs/block-10mm.json" + set}};
    const auto run = [&](const std::string& name, int ranks) {
        const std::string launcher =
            ranks > 0 ? "mpirun --oversubscribe --bind-to none -np " + std::to_string(ranks) + " "
                      : "";
        const fs::path dir = work / name;
        nlohmann::json r = {{"seconds", timed(launcher + vpsim + " -q run " + job + " --out " +
                                              dir.string() + set + " >/dev/null 2>&1")},
                            {"expose_seconds", stage(dir / "report.json", "expose")}};
        return r;
    };
    const fs::path plain = work / (tag + "tiled-plain");
    out["plain"] = run(tag + "tiled-plain", 0);
    const nlohmann::json plainFigures = figures(plain / "report.json");
    const std::string plainStl = file(plain / "cured.stl");
    const auto plainPictures = pictureFiles(plain);
    out["picture_files"] = plainPictures.size();
    for (int ranks : {1, 2, 4}) {
        const std::string name = tag + "tiled-" + std::to_string(ranks);
        nlohmann::json r = run(name, ranks);
        r["figures_equal_plain"] =
            !plainFigures.is_null() && figures(work / name / "report.json") == plainFigures;
        r["cured_stl_equal_plain"] =
            !plainStl.empty() && file(work / name / "cured.stl") == plainStl;
        if (!plainPictures.empty())
            r["pictures_equal_plain"] = pictureFiles(work / name) == plainPictures;
        out["ranks"][std::to_string(ranks)] = r;
    }
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    std::string photons = "400000";
    for (int i = 1; i + 1 < argc; ++i)
        if (std::string(argv[i]) == "--photons") photons = argv[i + 1];
    nlohmann::json out = {{"benchmark", "mpi"},
                          {"cores", std::thread::hardware_concurrency()},
                          {"load_average_1min_before", loadAverage()}};
    if (!vpsim::cluster::builtWithMpi() || std::system("command -v mpirun >/dev/null") != 0) {
        out["skipped"] = "built without MPI or mpirun missing (libopenmpi-dev, openmpi-bin)";
        std::cout << out.dump(2) << std::endl;
        return 0;
    }
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    setenv("OMPI_MCA_btl_vader_single_copy_mechanism", "none", 1);
    const fs::path work =
        fs::temp_directory_path() / ("vpsim_bench_mpi_" + std::to_string(getpid()));
    fs::create_directories(work);
    const std::string source = VPSIM_SOURCE_DIR, vpsim = VPSIM_CLI;
    const std::string job = source + "/tests/cli/data/small_job.json";
    const std::string set = " --set kernel.photons=" + photons;
    out["job"] = "tests/cli/data/small_job.json" + set;

    // One job: a fresh kernel cache per run, so every run computes its kernel.
    const auto run = [&](const std::string& name, int ranks) {
        const std::string launcher =
            ranks > 0 ? "mpirun --oversubscribe --bind-to none -np " + std::to_string(ranks) + " "
                      : "";
        const std::string command = "VPSIM_CACHE_DIR=" + (work / ("cache-" + name)).string() + " " +
                                    launcher + vpsim + " -q run " + job + " --out " +
                                    (work / name).string() + set + " >/dev/null 2>&1";
        nlohmann::json r = {{"seconds", timed(command)},
                            {"kernel_seconds", kernelSeconds(work / name / "report.json")}};
        return r;
    };
    out["plain"] = run("plain", 0);
    const nlohmann::json plainFigures = figures(work / "plain" / "report.json");
    nlohmann::json byRanks, speedup, batch;
    for (int ranks : {1, 2, 4}) {
        const std::string name = "ranks" + std::to_string(ranks);
        nlohmann::json r = run(name, ranks);
        r["figures_equal_plain"] =
            !plainFigures.is_null() && figures(work / name / "report.json") == plainFigures;
        byRanks[std::to_string(ranks)] = r;
    }
    for (int ranks : {2, 4})
        speedup[std::to_string(ranks)] =
            byRanks["1"]["kernel_seconds"].get<double>() /
            byRanks[std::to_string(ranks)]["kernel_seconds"].get<double>();
    out["run"] = byRanks;
    out["kernel_speedup_vs_1_rank"] = speedup;

    // A batch of 4 jobs (a sweep of the critical dose, 20000 photons each) over 1, 2 and 4 ranks.
    {
        std::ofstream sweep(work / "sweep.json");
        sweep << "{\"job\": \"" << job << "\", \"runs\": [";
        for (int d = 0; d < 4; ++d)
            sweep << (d ? "," : "") << "{\"name\": \"d" << d
                  << "\", \"set\": [\"cure.critical_dose=" << 8 + 2 * d << " mJ/cm^2\"]}";
        sweep << "]}";
    }
    nlohmann::json batchSeconds, batchEqual = true;
    for (int ranks : {1, 2, 4}) {
        const std::string dir = (work / ("batch" + std::to_string(ranks))).string();
        batchSeconds[std::to_string(ranks)] =
            timed("VPSIM_CACHE_DIR=" + dir + "-cache mpirun --oversubscribe --bind-to none -np " +
                  std::to_string(ranks) + " " + vpsim + " -q batch --sweep " +
                  (work / "sweep.json").string() + " --out " + dir + " >/dev/null 2>&1");
        for (int d = 0; d < 4; ++d) {
            const std::string jobDir = "/d" + std::to_string(d) + "/report.json";
            batchEqual = batchEqual.get<bool>() &&
                         figures(dir + jobDir) ==
                             figures(work / "batch1" / ("d" + std::to_string(d)) / "report.json");
        }
    }
    out["batch"] = {{"jobs", 4}, {"seconds", batchSeconds}, {"figures_equal_1_rank", batchEqual}};
    const std::string block = source + "/benchmarks/jobs/block-10mm.json";
    out["tiles"] = tiledRuns(work, vpsim, block, "[\"cured.stl\"]");
    out["tiles_with_pictures"] =
        tiledRuns(work, vpsim, block, "[\"cured.stl\", \"figures\", \"viewer\"]");
    out["load_average_1min_after"] = loadAverage();
    std::cout << out.dump(2) << std::endl;
    fs::remove_all(work);
    return 0;
}
