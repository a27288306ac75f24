#include "vpsim/report/html_report.h"

#include <filesystem>
#include <sstream>

#include "vpsim/core/io.h"
#include "vpsim/core/text.h"

namespace vpsim::report {
namespace {

std::string number(double value, int digits = 4) {
    return formatNumber(value, digits);
}

void figure(std::ostringstream& html, const std::string& outDir, const std::string& file,
            const std::string& caption) {
    std::error_code missing;
    if (!std::filesystem::exists(outDir + "/" + file, missing)) return;
    html << "<figure><img src='" << htmlEscape(file) << "' alt='" << htmlEscape(caption)
         << "'><figcaption>" << htmlEscape(caption) << "</figcaption></figure>\n";
}

/// A component's section: its tables, then its figures (those present in outDir).
void section(std::ostringstream& html, const std::string& outDir, const ReportSection& s) {
    html << "<h2>" << htmlEscape(s.title) << "</h2>\n";
    for (const ReportTable& table : s.tables) {
        html << "<table><tr>";
        for (const std::string& cell : table.header) html << "<th>" << htmlEscape(cell) << "</th>";
        html << "</tr>\n";
        for (const auto& cells : table.rows) {
            html << "<tr>";
            for (size_t i = 0; i < cells.size(); ++i)
                html << (i == 0 ? "<th>" : "<td>") << htmlEscape(cells[i])
                     << (i == 0 ? "</th>" : "</td>");
            html << "</tr>\n";
        }
        html << "</table>\n";
    }
    for (const ReportFigure& f : s.figures) figure(html, outDir, f.file, f.caption);
}

void row(std::ostringstream& html, const std::string& name, const std::string& value) {
    html << "<tr><th>" << name << "</th><td>" << value << "</td></tr>\n";
}

}  // namespace

void writeHtmlReport(const std::string& outDir, const JobResult& r) {
    std::ostringstream html;
    const std::string name = htmlEscape(r.name);
    html << "<!doctype html><html><head><meta charset='utf-8'><title>vpsim: " << name
         << "</title><style>body{font-family:sans-serif;margin:2em;max-width:1100px}"
            "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:4px "
            "10px;text-align:left}"
            "figure{display:inline-block;margin:1em;vertical-align:top}img{max-width:520px;border:"
            "1px solid #ddd}"
            "</style></head><body>\n";
    html << "<h1>vpsim run: " << name << "</h1>\n<p>Job <code>" << htmlEscape(r.jobFile)
         << "</code>, plan <code>" << htmlEscape(r.plan.strategy) << "</code>, backend "
         << htmlEscape(r.backend) << ".</p>\n";
    const validate::SurfaceDeviation& dev = r.validation.deviation;
    const validate::SliceValidationSummary& slices = r.validation.slices;
    html << "<h2>Cured part against the model</h2>\n<table>\n";
    row(html, "volume IoU", number(slices.iou));
    row(html, "surface deviation (mm)",
        "mean " + number(dev.mean) + ", RMS " + number(dev.rms) + ", 95th percentile " +
            number(dev.p95) + ", max " + number(dev.max));
    row(html, "over-cure below down-facing surfaces (mm)",
        number(slices.overcureBelowDownFacingMedian));
    row(html, "XY contour error (mm)",
        "mean " + number(slices.xyContourErrorMean) + ", max " + number(slices.xyContourErrorMax));
    row(html, "part / cured volume (mm&sup3;)",
        number(r.part.volume) + " / " + number(r.curedVolume));
    html << "</table>\n";
    const validate::FeatureMeasurements& f = r.validation.features;
    if (!f.probes.empty()) {
        html << "<h2>Features (mm)</h2>\n<table><tr><th>feature</th><th>objective</th>"
                "<th>simulated</th><th>measured mean</th></tr>\n";
        for (size_t i = 0; i < f.probes.size(); ++i) {
            const validate::FeatureProbe& p = f.probes[i];
            double mean = 0;
            for (double m : p.measured) mean += m / double(p.measured.size());
            html << "<tr><th>" << htmlEscape(p.name) << "</th><td>" << number(p.objective)
                 << "</td><td>" << number(f.simulated[i]) << "</td><td>"
                 << (p.measured.empty() ? "" : number(mean)) << "</td></tr>\n";
        }
        html << "</table>\n";
    }
    for (const ReportSection& s : r.sections) section(html, outDir, s);
    html << "<h2>Pictures</h2><p>Exposure in mJ/mm&sup2; from 0 to twice the critical dose; red: "
            "the model's outline, white: the cured outline at the critical dose.</p>\n";
    figure(html, outDir, "exposure_xz.png", "x-z cross-section through the middle of the part");
    figure(html, outDir, "exposure_xy.png", "x-y exposure of the middle layer");
    figure(html, outDir, "deviation_map_top.png",
           "cured surface from above, coloured by its largest deviation (blue inside the model, "
           "red outside)");
    figure(html, outDir, "deviation_histogram.svg", "histogram of the signed surface deviation");
    figure(html, outDir, "xy_error_per_layer.svg", "XY contour error per layer");
    figure(html, outDir, "scan_path.svg",
           "scan path of the busiest layer: marks, jumps within and between parts, part order");
    figure(html, outDir, "kernel/intensity_scattered.png",
           "beam kernel with scattering (Monte Carlo)");
    figure(html, outDir, "kernel/intensity_no_scattering.png", "beam kernel without scattering");
    figure(html, outDir, "kernel/radius_vs_depth.svg", "beam radius against depth");
    if (r.plan.planner.contains("build_time_s")) {
        const nlohmann::json& t = r.plan.planner["build_time_s"];
        html << "<h2>Build time (s, seed 002 Eq. 1-4)</h2><table>\n";
        for (const char* key : {"total", "mark", "jump", "delays", "recoat", "exposure"})
            if (t.contains(key))
                row(html, key, t[key].is_number() ? number(t[key].get<double>(), 4) : "unknown");
        if (t.contains("note")) row(html, "note", htmlEscape(t["note"].get<std::string>()));
        html << "</table>\n";
    }
    html << "<h2>Stages (s)</h2><table>\n";
    for (const auto& [stage, seconds] : r.stageSeconds) row(html, stage, number(seconds, 3));
    html << "</table>\n<h2>Files</h2><p><a href='report.json'>report.json</a>, <a "
            "href='part.stl'>part.stl</a>, <a href='cured.stl'>cured.stl</a>, <a "
            "href='plan.json'>plan.json</a>, exposure.vdb, reference.vdb";
    for (const std::string& file : r.exports)
        html << ", <a href='" << htmlEscape(file) << "'>" << htmlEscape(file) << "</a>";
    html << "</p>\n</body></html>\n";
    writeFileAtomic(outDir + "/index.html", html.str());
}

}  // namespace vpsim::report
