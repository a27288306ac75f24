#include "vpsim/report/compare_page.h"

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/output_directory.h"
#include "vpsim/core/progress.h"
#include "vpsim/core/text.h"
#include "vpsim/plot/plot.h"
#include "vpsim/report/html_report.h"
#include "vpsim/report/summary_tables.h"

namespace vpsim::report {
namespace {

struct Run {
    std::string dir, label;
    nlohmann::json report;
    std::vector<ManifestEntry> files;
};

const plot::Rgb PALETTE[] = {{31, 119, 180},  {255, 127, 14}, {44, 160, 44},   {214, 39, 40},
                             {148, 103, 189}, {140, 86, 75},  {227, 119, 194}, {127, 127, 127}};

/// Per-layer curves of all runs: `pick(layer entry)` -> (x, y) from report.json's array at
/// `path` (validation.layers, layer_exposure_error.layers).
template <typename Pick>
bool overlay(const std::vector<Run>& runs, const char* section, plot::LineFigure& figure,
             Pick pick) {
    bool any = false;
    for (size_t i = 0; i < runs.size(); ++i) {
        const nlohmann::json& r = runs[i].report;
        if (!r.contains(section) || !r[section].contains("layers")) continue;
        plot::Curve c{runs[i].label, {}, {}, PALETTE[i % 8], i >= 8};
        for (const nlohmann::json& layer : r[section]["layers"]) {
            double x = 0, y = 0;
            if (pick(layer, x, y)) c.x.push_back(x), c.y.push_back(y);
        }
        any = any || !c.x.empty();
        figure.curves.push_back(c);
    }
    return any;
}

Run loadRun(const std::string& dir) {
    OutputVerification v = requireVerifiedOutputDirectory(dir);
    Run run;
    run.dir = dir;
    run.files = v.entries;
    run.report = nlohmann::json::parse(readFile(dir + "/report.json", 64ull << 20), nullptr, false);
    if (run.report.is_discarded() || !run.report.is_object())
        throw InputError(dir + "/report.json is not a run's report (JSON object)");
    return run;
}

}  // namespace

std::string writeComparePage(const std::vector<std::string>& runDirs, const std::string& outDir) {
    if (runDirs.empty()) throw InputError("vpsim compare: no run directory given");
    std::vector<Run> runs;
    Progress progress("compare: run directories checked against their manifests", runDirs.size());
    for (const std::string& dir : runDirs) {
        runs.push_back(loadRun(dir));
        progress.advance();
    }
    progress.finish();
    std::vector<std::string> labels;
    for (size_t i = 0; i < runs.size(); ++i) {
        const nlohmann::json& r = runs[i].report;
        runs[i].label =
            std::to_string(i + 1) + ": " + humanValue(r.value("name", nlohmann::json())) + " (" +
            humanValue(r.contains("plan") ? r["plan"].value("strategy", nlohmann::json())
                                          : nlohmann::json()) +
            ")";
        labels.push_back(runs[i].label);
    }
    OutputDirectory output(outDir, {{"command", "compare"}, {"runs", runDirs}});
    // Figures copied per run, so the page stays whole when the runs move.
    std::vector<std::vector<std::string>> copied(runs.size());
    for (size_t i = 0; i < runs.size(); ++i) {
        const std::string folder = "run-" + std::to_string(i + 1);
        for (const RunFigure& f : RUN_FIGURES) {
            std::string file = f.file;
            if (file.find('.') == std::string::npos) file += ".svg";
            for (const ManifestEntry& e : runs[i].files)
                if (e.name == file) {
                    output.writeFile(folder + "/" + file, readFile(runs[i].dir + "/" + file));
                    copied[i].push_back(folder + "/" + file);
                }
        }
    }
    plot::LineFigure xy{"XY contour error per layer", "z (mm)", "mean XY error (µm)", {}, "", true};
    const bool haveXy =
        overlay(runs, "validation", xy, [](const nlohmann::json& l, double& x, double& y) {
            if (!l.contains("xy_contour_error_mm") || l.value("reference_area_mm2", 0.0) <= 0)
                return false;
            x = l.value("z", 0.0), y = l["xy_contour_error_mm"].get<double>() * 1000;
            return true;
        });
    if (haveXy) plot::writeLineFigure(outDir + "/compare_xy_error", xy);
    plot::LineFigure laser{
        "Laser exposure error per layer (seed 000)", "layer", "RMS |E - Etm| / Etar", {}, "", true};
    const bool haveLaser = overlay(runs, "layer_exposure_error", laser,
                                   [](const nlohmann::json& l, double& x, double& y) {
                                       if (!l.contains("rms_over_Etar")) return false;
                                       x = l.value("layer", 0.0) + 1;
                                       y = l["rms_over_Etar"].get<double>();
                                       return true;
                                   });
    if (haveLaser) plot::writeLineFigure(outDir + "/compare_exposure_error", laser);

    std::ostringstream html;
    html << "<!doctype html><html><head><meta charset='utf-8'><title>vpsim compare</title><style>"
            "body{font-family:sans-serif;margin:2em}table{border-collapse:collapse;margin:.3em 0}"
            "td,th{border:1px solid #ccc;padding:3px 8px;text-align:left;vertical-align:top}"
            "th{background:#f6f6f6;font-weight:normal}img{max-width:480px}"
            "</style></head><body>\n<h1>vpsim compare: "
         << runs.size() << " runs</h1>\n";
    ReportTable list{{"run", "directory", "job file"}, {}};
    for (const Run& r : runs)
        list.rows.push_back({r.label, r.dir, humanValue(r.report.value("job", nlohmann::json()))});
    html << tableHtml(list);
    auto columns = [&](auto tablesOf) {
        std::vector<std::vector<SummaryTable>> perRun;
        for (const Run& r : runs) perRun.push_back(tablesOf(r.report));
        std::vector<std::string> titles;  // in first appearance, matched by title
        for (const auto& tables : perRun)
            for (const SummaryTable& t : tables)
                if (std::find(titles.begin(), titles.end(), t.title) == titles.end())
                    titles.push_back(t.title);
        for (const std::string& title : titles) {
            std::vector<ReportTable> tables;
            for (const auto& run : perRun) {
                tables.emplace_back();
                for (const SummaryTable& t : run)
                    if (t.title == title) tables.back() = t.table;
            }
            ReportTable merged = sideBySide(tables, labels);
            if (merged.rows.empty()) continue;
            html << "<h3>" << htmlEscape(title) << "</h3>\n" << tableHtml(merged);
        }
    };
    html << "<h2>Verdicts</h2>\n";
    columns([](const nlohmann::json& r) { return std::vector<SummaryTable>{verdictTable(r)}; });
    html << "<h2>Features</h2><p>Each cell: predicted | objective | measured | predicted - "
            "objective | predicted - measured (mm).</p>\n";
    columns([](const nlohmann::json& r) { return std::vector<SummaryTable>{featuresTable(r)}; });
    html << "<h2>Exposure-error curves</h2>\n";
    for (const auto& [have, stem] : {std::pair<bool, const char*>{haveXy, "compare_xy_error"},
                                     {haveLaser, "compare_exposure_error"}})
        if (have)
            html << "<figure><a href='" << stem << ".png'><img src='" << stem
                 << ".svg'></a></figure>\n";
    html << "<h2>Inputs</h2>\n";
    columns([](const nlohmann::json& r) { return inputTables(r); });
    html << "<h2>Figures</h2>\n<table><tr><th></th>";
    for (const std::string& l : labels) html << "<th>" << htmlEscape(l) << "</th>";
    html << "</tr>\n";
    for (const RunFigure& f : RUN_FIGURES) {
        std::string file = f.file;
        if (file.find('.') == std::string::npos) file += ".svg";
        bool any = false;
        for (const auto& c : copied)
            for (const std::string& name : c)
                any = any || (name.size() >= file.size() &&
                              name.compare(name.size() - file.size(), file.size(), file) == 0);
        if (!any) continue;
        html << "<tr><th>" << htmlEscape(f.caption) << "</th>";
        for (size_t i = 0; i < runs.size(); ++i) {
            const std::string name = "run-" + std::to_string(i + 1) + "/" + file;
            bool here = false;
            for (const std::string& c : copied[i]) here = here || c == name;
            html << "<td>";
            if (here)
                html << "<a href='" << htmlEscape(name) << "'><img src='" << htmlEscape(name)
                     << "' alt='" << htmlEscape(f.caption) << "'></a>";
            html << "</td>";
        }
        html << "</tr>\n";
    }
    html << "</table>\n</body></html>\n";
    output.writeFile("index.html", html.str());
    output.finish();
    return outDir + "/index.html";
}

}  // namespace vpsim::report
