#include "report/html_report.h"

#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>

#include "vpsim/core/io.h"

namespace vpsim::report {
namespace {

std::string number(const nlohmann::json& value, int digits = 4) {
    if (!value.is_number()) return value.dump();
    std::ostringstream text;
    text.precision(digits);
    text << value.get<double>();
    return text.str();
}

void figure(std::ostringstream& html, const std::string& outDir, const std::string& file,
            const std::string& caption) {
    if (!std::filesystem::exists(outDir + "/" + file)) return;
    html << "<figure><img src='" << file << "' alt='" << caption << "'><figcaption>" << caption
         << "</figcaption></figure>\n";
}

}  // namespace

void writeHtmlReport(const std::string& outDir, const nlohmann::json& report) {
    std::ostringstream html;
    html << "<!doctype html><html><head><meta charset='utf-8'><title>vpsim: "
         << report.value("name", "")
         << "</title><style>body{font-family:sans-serif;margin:2em;max-width:1100px}"
            "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:4px "
            "10px;text-align:left}"
            "figure{display:inline-block;margin:1em;vertical-align:top}img{max-width:520px;border:"
            "1px solid #ddd}"
            "</style></head><body>\n";
    html << "<h1>vpsim run: " << report.value("name", "") << "</h1>\n<p>Job <code>"
         << report.value("job", "") << "</code>, backend " << report.value("backend", "")
         << ".</p>\n";
    const auto& dev = report["surface_deviation_mm"];
    html << "<h2>Cured part against the model</h2>\n<table>\n"
         << "<tr><th>volume IoU</th><td>" << number(report["iou"]) << "</td></tr>\n"
         << "<tr><th>surface deviation (mm)</th><td>mean " << number(dev["mean"]) << ", RMS "
         << number(dev["rms"]) << ", 95th percentile " << number(dev["p95"]) << ", max "
         << number(dev["max"]) << "</td></tr>\n"
         << "<tr><th>over-cure below down-facing surfaces (mm)</th><td>"
         << number(report["overcure_below_downfacing_mm"]) << "</td></tr>\n"
         << "<tr><th>XY contour error (mm)</th><td>mean "
         << number(report["validation"]["xy_contour_error_mm"]["mean"]) << ", max "
         << number(report["validation"]["xy_contour_error_mm"]["max"]) << "</td></tr>\n"
         << "<tr><th>part / cured volume (mm&sup3;)</th><td>"
         << number(report["part"]["volume_mm3"]) << " / " << number(report["cured_volume_mm3"])
         << "</td></tr>\n</table>\n";
    html << "<h2>Pictures</h2><p>Exposure in mJ/mm&sup2; from 0 to twice the critical dose; red: "
            "the model's "
            "outline, white: the cured outline at the critical dose.</p>\n";
    figure(html, outDir, "exposure_xz.png", "x-z cross-section through the middle of the part");
    figure(html, outDir, "exposure_xy.png", "x-y exposure of the middle layer");
    figure(html, outDir, "deviation_map_top.png",
           "cured surface from above, coloured by its largest deviation (blue inside the model, "
           "red outside)");
    figure(html, outDir, "deviation_histogram.svg", "histogram of the signed surface deviation");
    figure(html, outDir, "xy_error_per_layer.svg", "XY contour error per layer");
    figure(html, outDir, "kernel/intensity_scattered.png",
           "beam kernel with scattering (Monte Carlo)");
    figure(html, outDir, "kernel/intensity_no_scattering.png", "beam kernel without scattering");
    figure(html, outDir, "kernel/radius_vs_depth.svg", "beam radius against depth");
    html << "<h2>Stages (s)</h2><table>\n";
    for (const auto& [stage, seconds] : report["stage_seconds"].items())
        html << "<tr><th>" << stage << "</th><td>" << number(seconds, 3) << "</td></tr>\n";
    html << "</table>\n<h2>Files</h2><p><a href='report.json'>report.json</a>, <a "
            "href='part.stl'>part.stl</a>, "
            "<a href='cured.stl'>cured.stl</a>, <a href='plan.json'>plan.json</a>, exposure.vdb, "
            "reference.vdb</p>\n"
            "</body></html>\n";
    writeFileAtomic(outDir + "/index.html", html.str());
}

}  // namespace vpsim::report
