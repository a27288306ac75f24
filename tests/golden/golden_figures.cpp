// vpsim_golden: the golden-figures comparer (tests/golden/README.md).
//   vpsim_golden run-args JOB.json
//       prints the vpsim arguments the golden run of JOB.json uses, one per line.
//   vpsim_golden flatten REPORT.json
//       prints the report's figures as one flat JSON object {"path": number}.
//   vpsim_golden compare FIGURES.json JOB REPORT.json [RUN_ARGS...]
//       prints a table of JOB's stored figures beside those of REPORT.json (stored, now,
//       difference, tolerance, OK/MOVED/MISSING/NEW); exit 0 when all are within tolerance, 1 when
//       any moved, 2 when JOB has no stored values or was stored with other RUN_ARGS.
//   vpsim_golden reset FIGURES.json
//       removes every job's stored figures, keeping the tolerances (tools/update-golden.sh).
//   vpsim_golden store FIGURES.json JOB REPORT.json [RUN_ARGS...]
//       stores REPORT.json's figures as JOB's, run with RUN_ARGS (tools/update-golden.sh).
//
// Figures are every number in report.json except timings (keys ending in "seconds"), the
// per-layer table validation.layers (its summary validation.xy_contour_error_mm is kept),
// values that depend on the run rather than the physics (kernel.from_cache), the job's own
// inputs echoed back (inputs) and the report's presentation data (report: picture scales, the
// 3D view's mesh sizes). Features are keyed
// by name: "features[top hole height].simulated_mm".

#include <fnmatch.h>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace {

using nlohmann::json;
using Figures = std::map<std::string, double>;

constexpr int GOLDEN_PHOTONS = 100000;

json readJson(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot read");
    try {
        return json::parse(in);
    } catch (const json::exception& e) {
        throw std::runtime_error(path + ": " + e.what());
    }
}

bool skipped(const std::string& path, const std::string& key) {
    auto endsWith = [&](const std::string& s) {
        return key.size() >= s.size() && key.compare(key.size() - s.size(), s.size(), s) == 0;
    };
    return endsWith("seconds") || path == "validation.layers" || path == "kernel.from_cache" ||
           path == "inputs" || path == "report";
}

void flatten(const json& value, const std::string& path, Figures& out) {
    if (value.is_number()) {
        out[path] = value.get<double>();
    } else if (value.is_object()) {
        for (const auto& [key, child] : value.items()) {
            std::string childPath = path.empty() ? key : path + "." + key;
            if (!skipped(childPath, key)) flatten(child, childPath, out);
        }
    } else if (value.is_array()) {
        for (size_t i = 0; i < value.size(); ++i) {
            const json& child = value[i];
            // Elements with a name (features) are keyed by it, so reordering moves nothing.
            std::string index =
                child.is_object() && child.contains("name") && child["name"].is_string()
                    ? child["name"].get<std::string>()
                    : std::to_string(i);
            flatten(child, path + "[" + index + "]", out);
        }
    }
}

struct Tolerance {
    double abs = 0, rel = 0;
    std::string match;
};

Tolerance toleranceFor(const json& rules, const std::string& figure) {
    for (const auto& rule : rules) {
        std::string pattern = rule.at("match");
        if (fnmatch(pattern.c_str(), figure.c_str(), 0) == 0)
            return {rule.value("abs", 0.0), rule.value("rel", 0.0), pattern};
    }
    throw std::runtime_error("no tolerance rule matches figure '" + figure +
                             "' (the last rule should be \"*\")");
}

std::string number(double v, int digits = 10) {
    char text[40];
    std::snprintf(text, sizeof text, "%.*g", digits, v);
    return text;
}

int compare(const std::string& figuresFile, const std::string& job, const std::string& report,
            const json& runArgs) {
    json stored = readJson(figuresFile);
    const std::string update = "run `bash tools/update-golden.sh` and commit " + figuresFile +
                               " with a message saying why the figures changed";
    if (!stored["jobs"].contains(job)) {
        std::cout << "golden: job '" << job << "' has no stored figures in " << figuresFile
                  << "; to add them, run `bash tools/update-golden.sh` and commit " << figuresFile
                  << " (a new examples/*.json job needs its figures stored)\n";
        return 2;
    }
    const json& entry = stored["jobs"][job];
    if (entry.value("run_args", json::array()) != runArgs) {
        std::cout << "golden: job '" << job << "' was stored with run_args "
                  << entry.value("run_args", json::array()).dump() << ", now run with "
                  << runArgs.dump() << ": " << update << "\n";
        return 2;
    }
    Figures now, before = entry.at("figures").get<Figures>();
    flatten(readJson(report), "", now);
    std::map<std::string, int> all;
    for (const auto& f : before) all[f.first] = 1;
    for (const auto& f : now) all[f.first] = 1;

    int moved = 0;
    std::printf("%-56s %17s %17s %10s %10s  %s\n", ("job " + job).c_str(), "stored", "now",
                "difference", "tolerance", "");
    for (const auto& [name, unused] : all) {
        auto b = before.find(name), n = now.find(name);
        std::string status, s = "-", c = "-", d = "-", t = "-";
        if (b == before.end()) {
            status = "NEW";
            c = number(n->second);
        } else if (n == now.end()) {
            status = "MISSING";
            s = number(b->second);
        } else {
            Tolerance tol = toleranceFor(stored.at("tolerances"), name);
            double allowed = tol.abs + tol.rel * std::abs(b->second);
            double diff = n->second - b->second;
            status = std::abs(diff) <= allowed ? "OK" : "MOVED";
            s = number(b->second);
            c = number(n->second);
            d = number(diff, 3);
            t = number(allowed, 3);
        }
        if (status != "OK") ++moved;
        std::printf("%-56s %17s %17s %10s %10s  %s\n", name.c_str(), s.c_str(), c.c_str(),
                    d.c_str(), t.c_str(), status.c_str());
    }
    std::printf("job %s: %zu figures, %d not OK\n", job.c_str(), all.size(), moved);
    if (moved)
        std::cout << "golden: figures of '" << job << "' moved; if the change is deliberate, "
                  << update << "\n";
    return moved ? 1 : 0;
}

void writeAtomically(const std::string& path, const json& value) {
    std::string temporary = path + ".tmp";
    {
        std::ofstream out(temporary);
        out << value.dump(2) << "\n";
        if (!out) throw std::runtime_error(temporary + ": cannot write");
    }
    if (std::rename(temporary.c_str(), path.c_str()) != 0)
        throw std::runtime_error(path + ": cannot replace");
}

/// Sets JOB's stored figures from REPORT.json; `reset` (empty job) clears all jobs.
int store(const std::string& figuresFile, const std::string& job, const std::string& report,
          const json& runArgs) {
    json stored = readJson(figuresFile);
    if (job.empty()) {
        stored["jobs"] = json::object();
    } else {
        Figures figures;
        flatten(readJson(report), "", figures);
        stored["jobs"][job] = {{"run_args", runArgs}, {"figures", figures}};
    }
    writeAtomically(figuresFile, stored);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    try {
        if (args.size() == 2 && args[0] == "flatten") {
            Figures figures;
            flatten(readJson(args[1]), "", figures);
            std::cout << json(figures).dump(2) << "\n";
            return 0;
        }
        if (args.size() >= 4 && args[0] == "compare")
            return compare(args[1], args[2], args[3],
                           json(std::vector<std::string>(args.begin() + 4, args.end())));
        if (args.size() == 2 && args[0] == "run-args") {
            // A Monte Carlo kernel runs at a reduced photon count: 1e5 photons take ~2 s on
            // 2 cores instead of ~4 s for the examples' 3e5 (same seed, so still deterministic).
            json jobFile = readJson(args[1]);
            if (jobFile.contains("kernel") &&
                jobFile["kernel"].value("source", "") == "monte-carlo")
                std::cout << "--set\nkernel.photons=" << GOLDEN_PHOTONS << "\n";
            return 0;
        }
        if (args.size() == 2 && args[0] == "reset") return store(args[1], "", "", {});
        if (args.size() >= 4 && args[0] == "store")
            return store(args[1], args[2], args[3],
                         json(std::vector<std::string>(args.begin() + 4, args.end())));
    } catch (const std::exception& e) {
        std::cerr << "vpsim_golden: error: " << e.what() << "\n";
        return 3;
    }
    std::cerr << "usage: vpsim_golden run-args JOB.json | flatten REPORT.json | compare "
                 "FIGURES.json JOB REPORT.json "
                 "[RUN_ARGS...] | reset FIGURES.json | store FIGURES.json JOB REPORT.json "
                 "[RUN_ARGS...]\n";
    return 3;
}
