#include "vpsim/report/html_report.h"

#include <algorithm>
#include <sstream>

#include "vpsim/core/io.h"
#include "vpsim/core/text.h"
#include "vpsim/report/summary_tables.h"

namespace vpsim::report {

const std::vector<RunFigure> RUN_FIGURES = {
    {"exposure_xz",
     "x-z section of the exposure through the part's material, with the model's "
     "and the cured outlines"},
    {"exposure_xy", "x-y exposure of the middle layer, with the model's and the cured outlines"},
    {"deviation_map_top",
     "cured surface from above, coloured by the signed deviation of its top "
     "surface (blue inside the model, red outside)"},
    {"deviation_histogram", "histogram of the signed surface deviation"},
    {"xy_error_per_layer", "XY contour error per layer"},
    {"scan_path",
     "scan path of the busiest layer: marks, jumps within and between parts, "
     "part order"},
    {"kernel/intensity_scattered", "beam kernel I(r, z) with scattering (Monte Carlo)"},
    {"kernel/intensity_no_scattering", "beam kernel without scattering"},
    {"kernel/radius_vs_depth", "beam radius against depth, Monte Carlo and its Eq. 12 fit"},
};

namespace {

bool exists(const std::string& outDir, const std::string& file) {
    std::error_code missing;
    return std::filesystem::exists(outDir + "/" + file, missing);
}

/// A figure: the SVG shown (linked to its PNG when there is one), or a single file.
void figure(std::ostringstream& html, const std::string& outDir, const std::string& file,
            const std::string& caption) {
    const bool stem = file.find('.') == std::string::npos;
    const std::string shown = stem ? file + ".svg" : file;
    if (!exists(outDir, shown)) return;
    const std::string link = stem && exists(outDir, file + ".png") ? file + ".png" : shown;
    html << "<figure><a href='" << htmlEscape(link) << "'><img src='" << htmlEscape(shown)
         << "' alt='" << htmlEscape(caption) << "'></a><figcaption>" << htmlEscape(caption)
         << (stem ? " (<a href='" + htmlEscape(file) + ".png'>PNG</a>)" : std::string())
         << "</figcaption></figure>\n";
}

void titled(std::ostringstream& html, const SummaryTable& t, const char* level = "h3") {
    html << "<div class='card'><" << level << ">" << htmlEscape(t.title) << "</" << level << ">"
         << tableHtml(t.table) << "</div>\n";
}

/// A component's section: its tables, then its figures (those present in outDir).
void section(std::ostringstream& html, const std::string& outDir, const ReportSection& s) {
    html << "<h2>" << htmlEscape(s.title) << "</h2>\n";
    for (const ReportTable& table : s.tables) html << tableHtml(table);
    for (const ReportFigure& f : s.figures) figure(html, outDir, f.file, f.caption);
}

/// The per-layer section (synced with the 3D view's slider) and the kernel map, drawn by
/// section_view.js from sections.js.
void sectionPanels(std::ostringstream& html, const SectionViewSummary& s) {
    html << "<div class='panel'><canvas id='section2d' width='560' height='520'></canvas><p>"
            "Section through the layer at the slider: x-y exposure of its middle voxel slice "
            "(viridis, 0 to "
         << formatNumber(s.scaleMax, 3) << " mJ/cm², " << formatNumber(100 * s.aboveScale, 3)
         << "% of the pixels above, drawn at the top), the cured region (white dashed: at least "
            "the critical dose Dc) and the model's sliced outline (red). <span "
            "id='section2d-label'></span> Kept: "
         << s.layersKept << " of " << s.layers << " layers at " << s.width << " x " << s.height
         << " pixels of " << formatNumber(s.pixelMm * 1000, 3) << " µm (sections.js, "
         << formatNumber(double(s.dataBytes) / 1048576.0, 3) << " MB).</p></div>\n";
    if (s.kernel)
        html << "<div class='panel' id='kernel-panel'><canvas id='kernel2d' width='560' "
                "height='460'></canvas><p>Beam kernel I(r, z) of the Monte Carlo in mW/mm² "
                "(log colour scale, four decades below its maximum), r from the beam axis and "
                "depth from the surface in µm; white: contours of the fitted Eq. 12 model at each "
                "decade; red dashed: the depth where the fit starts (zmax).</p></div>\n";
}

void viewer(std::ostringstream& html, const JobResult& r, bool withSections) {
    html << "<h2 id='view3d-title'>The cured part in 3D (<a href='view3d.html'>alone</a>)</h2>\n"
            "<div class='views'>\n";
    const bool shown = r.viewer && r.viewer->missing.empty();
    if (r.viewer && !shown) html << "<p>No 3D view: " << htmlEscape(r.viewer->missing) << ".</p>\n";
    if (shown) {
        const ViewerSummary& v = *r.viewer;
        const std::string limit = formatNumber(v.limitUm, 3);
        html << "<div class='view3d'><canvas id='view3d' width='600' height='560'></canvas>"
                "<div class='controls'><label><input type='checkbox' id='view3d-model' checked> "
                "model (grey, edges dark)</label> <label>layer: <input type='range' "
                "id='view3d-clip' min='0' max='1' step='1' value='1'></label> <span "
                "id='view3d-clip-label'>whole part</span><div class='legend'><span>-"
             << limit << " µm</span><span class='bar'></span><span>+" << limit
             << " µm</span> signed deviation of the cured surface (blue inside the model, red "
                "outside; beyond the ends at their colour)</div><p id='view3d-status'>Drag to "
                "rotate, wheel to zoom, right-drag to pan; the slider cuts the view at a layer's "
                "top and shows that layer's section.</p></div></div>\n";
    } else if (withSections && r.sectionView) {
        html << "<label>layer: <input type='range' id='view3d-clip' min='1' max='1' step='1' "
                "value='1'></label>\n";
    }
    if (withSections && r.sectionView) sectionPanels(html, *r.sectionView);
    html << "</div>\n";
    if (!shown) return;
    const ViewerSummary& v = *r.viewer;
    html << "<p>Shown: " << v.curedShown << " of the cured surface's " << v.curedTriangles
         << " triangles";
    if (v.clusterCell > 0)
        html << " (decimated for the view by vertex clustering on "
             << formatNumber(v.clusterCell * 1000, 3) << " µm cells, "
             << formatNumber(100.0 * (1.0 - double(v.curedShown) / double(v.curedTriangles)), 3)
             << "% fewer; cured.stl is whole)";
    html << ", " << v.modelShown << " of the model's " << v.modelTriangles
         << "; the view's data is " << formatNumber(double(v.dataBytes) / 1048576.0, 3)
         << " MB (mesh3d.js), the report is kept under 50 MB.</p>\n";
}

/// The 3D view's and the sections' scripts, classic and local (file:// blocks the rest).
std::string viewerScripts(const JobResult& r, bool withSections) {
    std::string scripts;
    if (r.viewer && r.viewer->missing.empty())
        scripts +=
            "<script src='three.min.js'></script><script src='OrbitControls.js'></script>"
            "<script src='mesh3d.js'></script><script src='viewer3d.js'></script>";
    if (withSections && r.sectionView)
        scripts += "<script src='sections.js'></script><script src='section_view.js'></script>";
    return scripts + "\n";
}

std::string bytesText(uint64_t bytes) {
    if (bytes < 1024) return std::to_string(bytes) + " B";
    if (bytes < 1048576) return formatNumber(double(bytes) / 1024, 3) + " kB";
    return formatNumber(double(bytes) / 1048576, 3) + " MB";
}

}  // namespace

std::vector<WrittenFile> filesWrittenSince(const std::string& outDir,
                                           std::filesystem::file_time_type since) {
    std::vector<WrittenFile> files;
    std::error_code error;
    namespace fs = std::filesystem;
    for (fs::recursive_directory_iterator it(outDir, error), end; !error && it != end;
         it.increment(error)) {
        if (!it->is_regular_file(error)) continue;
        const std::string name = fs::relative(it->path(), outDir, error).generic_string();
        if (name.find(".tmp.") != std::string::npos || name == "manifest.json") continue;
        if (it->last_write_time(error) < since) continue;
        files.push_back({name, uint64_t(it->file_size(error))});
    }
    std::sort(files.begin(), files.end(),
              [](const WrittenFile& a, const WrittenFile& b) { return a.name < b.name; });
    return files;
}

void writeHtmlReport(const std::string& outDir, const JobResult& r) {
    const nlohmann::json report = toJson(r);
    std::ostringstream html;
    const std::string name = htmlEscape(r.name);
    html << "<!doctype html><html><head><meta charset='utf-8'><title>vpsim: " << name
         << "</title><style>body{font-family:sans-serif;margin:2em;max-width:1250px}"
            "table{border-collapse:collapse;margin:.3em 0}td,th{border:1px solid #ccc;padding:3px "
            "8px;text-align:left;vertical-align:top}th{background:#f6f6f6;font-weight:normal}"
            ".cards{display:flex;flex-wrap:wrap;gap:1em}.card h3{margin:.2em 0}"
            "figure{display:inline-block;margin:1em;vertical-align:top;max-width:600px}"
            "img{max-width:600px;border:1px solid #ddd}"
            "#view3d{width:600px;height:560px;border:1px solid #ccc;display:block}"
            ".views{display:flex;flex-wrap:wrap;gap:1em;align-items:flex-start}"
            ".view3d{max-width:600px}.panel{max-width:570px}.panel canvas{border:1px solid "
            "#ccc;display:block}"
            ".legend .bar{display:inline-block;width:220px;height:12px;margin:0 6px;"
            "background:linear-gradient(to right,#2166ab,#f7f7f7,#b2182b)}"
            "</style></head><body>\n";
    html << "<h1>vpsim run: " << name << "</h1>\n<p>";
    for (const char* anchor : {"inputs", "verdict", "view3d-title", "figures", "files"})
        html << "<a href='#" << anchor << "'>" << anchor << "</a> ";
    html << "</p>\n<h2 id='inputs'>Inputs</h2>\n<div class='cards'>\n";
    for (const SummaryTable& t : inputTables(report)) titled(html, t);
    html << "</div>\n<h2 id='verdict'>Verdict</h2>\n<div class='cards'>\n";
    titled(html, verdictTable(report));
    const SummaryTable features = featuresTable(report);
    if (!features.table.rows.empty()) titled(html, features);
    html << "</div>\n";
    if (r.viewer || r.sectionView) viewer(html, r, true);
    html << "<h2 id='figures'>Figures</h2>\n<p>Exposure in mJ/cm², deviation in µm; axes in mm at "
            "the true aspect ratio. Click a figure for its PNG.</p>\n";
    for (const RunFigure& f : RUN_FIGURES) figure(html, outDir, f.file, f.caption);
    for (const ReportSection& s : r.sections) section(html, outDir, s);
    if (r.plan.planner.contains("build_time_s")) {
        const nlohmann::json& t = r.plan.planner["build_time_s"];
        ReportTable table{{"", ""}, {}};
        for (const char* key : {"total", "mark", "jump", "delays", "recoat", "exposure"})
            if (t.contains(key))
                table.rows.push_back(
                    {key, t[key].is_number() ? formatNumber(t[key].get<double>(), 4) : "unknown"});
        if (t.contains("note")) table.rows.push_back({"note", humanValue(t["note"])});
        html << "<h2>Build time (s, seed 002 Eq. 1-4)</h2>" << tableHtml(table);
    }
    ReportTable stages{{"", ""}, {}};
    for (const auto& [stage, seconds] : r.stageSeconds)
        stages.rows.push_back({stage, formatNumber(seconds, 3)});
    html << "<h2>Stages (s)</h2>\n" << tableHtml(stages);
    html << "<h2 id='files'>Files</h2>\n<p>Written by this run; manifest.json lists each with its "
            "size and SHA-256.</p>\n<table><tr><th>file</th><th>size</th></tr>\n";
    std::vector<WrittenFile> files = r.files;
    files.push_back({"index.html", 0});
    files.push_back({"manifest.json", 0});
    for (const WrittenFile& f : files)
        html << "<tr><td><a href='" << htmlEscape(f.name) << "'>" << htmlEscape(f.name)
             << "</a></td><td>" << (f.bytes ? bytesText(f.bytes) : "") << "</td></tr>\n";
    html << "</table>\n";
    if (r.viewer || r.sectionView) html << viewerScripts(r, true);
    if (r.viewer && r.viewer->missing.empty()) {
        // The 3D view alone, for a full window (and the browser test's screenshot, which counts
        // its coloured pixels: the sections stay on index.html).
        std::ostringstream alone;
        alone << "<!doctype html><html><head><meta charset='utf-8'><title>vpsim 3D: " << name
              << "</title><style>body{font-family:sans-serif;margin:0}#view3d{width:100vw;height:"
                 "80vh;display:block}.legend .bar{display:inline-block;width:220px;height:12px;"
                 "background:linear-gradient(to right,#2166ab,#f7f7f7,#b2182b)}</style></head>"
                 "<body>\n";
        viewer(alone, r, false);
        alone << viewerScripts(r, false) << "</body></html>\n";
        writeFileAtomic(outDir + "/view3d.html", alone.str());
    }
    html << "</body></html>\n";
    writeFileAtomic(outDir + "/index.html", html.str());
}

}  // namespace vpsim::report
