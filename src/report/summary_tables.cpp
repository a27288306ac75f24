#include "vpsim/report/summary_tables.h"

#include <cmath>
#include <map>

#include "vpsim/core/text.h"

namespace vpsim::report {
namespace {

void addRows(ReportTable& table, const nlohmann::json& object, const std::string& prefix = "") {
    if (!object.is_object()) return;
    for (const auto& [key, value] : object.items()) {
        if (value.is_object()) {
            addRows(table, value, prefix + key + ".");
            continue;
        }
        if (value.is_array() && value.size() > 8) continue;  // per-layer lists: see report.json
        table.rows.push_back({humanKey(prefix + key), humanValue(value)});
    }
}

const nlohmann::json& at(const nlohmann::json& object, const char* key) {
    static const nlohmann::json none;
    return object.is_object() && object.contains(key) ? object[key] : none;
}

std::string num(const nlohmann::json& value, double scale = 1, const char* unit = "") {
    if (!value.is_number()) return "";
    return formatNumber(value.get<double>() * scale, 4) + unit;
}

}  // namespace

std::string humanKey(const std::string& key) {
    static const std::pair<const char*, const char*> units[] = {{"_mJ_per_cm2", " (mJ/cm²)"},
                                                                {"_mm_per_s", " (mm/s)"},
                                                                {"_mm3", " (mm³)"},
                                                                {"_mm2", " (mm²)"},
                                                                {"_um", " (µm)"},
                                                                {"_mm", " (mm)"},
                                                                {"_mJ", " (mJ)"},
                                                                {"_s", " (s)"},
                                                                {"_mW", " (mW)"}};
    std::string base = key, unit;
    for (const auto& [suffix, text] : units) {
        const std::string s = suffix;
        if (base.size() > s.size() && base.compare(base.size() - s.size(), s.size(), s) == 0) {
            base.resize(base.size() - s.size()), unit = text;
            break;
        }
    }
    for (char& c : base)
        if (c == '_') c = ' ';
    return base + unit;
}

std::string humanValue(const nlohmann::json& value) {
    if (value.is_number_integer() || value.is_number_unsigned()) return value.dump();
    if (value.is_number()) return formatNumber(value.get<double>(), 4);
    if (value.is_string()) return value.get<std::string>();
    if (value.is_boolean()) return value.get<bool>() ? "yes" : "no";
    if (value.is_array()) {
        std::string out;
        for (const auto& v : value) out += (out.empty() ? "" : ", ") + humanValue(v);
        return out;
    }
    if (value.is_null()) return "";
    return value.dump();
}

std::vector<SummaryTable> inputTables(const nlohmann::json& report) {
    std::vector<SummaryTable> out;
    const nlohmann::json& inputs = at(report, "inputs");
    const nlohmann::json& job = at(inputs, "job");
    SummaryTable head{"Job", {{"", ""}, {}}};
    head.table.rows.push_back({"job file", humanValue(at(report, "job"))});
    head.table.rows.push_back({"name", humanValue(at(report, "name"))});
    if (job.contains("description"))
        head.table.rows.push_back({"description", humanValue(job["description"])});
    head.table.rows.push_back({"backend", humanValue(at(report, "backend"))});
    out.push_back(head);
    if (at(inputs, "material").is_object()) {
        SummaryTable m{"Material", {{"", ""}, {}}};
        m.table.rows.push_back({"file", humanValue(at(job, "material"))});
        addRows(m.table, inputs["material"]);
        out.push_back(m);
    }
    for (const auto& [key, title] :
         std::vector<std::pair<const char*, const char*>>{{"cure", "Cure law"},
                                                          {"part", "Part"},
                                                          {"machine", "Machine"},
                                                          {"kernel", "Beam kernel"},
                                                          {"simulation", "Simulation grid"}}) {
        SummaryTable t{title, {{"", ""}, {}}};
        addRows(t.table, at(job, key));
        if (std::string(key) == "cure" && t.table.rows.empty())
            addRows(t.table, at(report, "cure"));
        if (std::string(key) == "part") {
            const nlohmann::json& part = at(report, "part");
            t.table.rows.push_back({"size (mm)", humanValue(at(part, "size_mm"))});
            t.table.rows.push_back({"volume (mm³)", num(at(part, "volume_mm3"))});
        }
        if (!t.table.rows.empty()) out.push_back(t);
    }
    SummaryTable plan{"Plan", {{"", ""}, {}}};
    const nlohmann::json& p = at(report, "plan");
    plan.table.rows.push_back({"strategy", humanValue(at(p, "strategy"))});
    plan.table.rows.push_back({"layers", humanValue(at(p, "layers"))});
    plan.table.rows.push_back({"energy (mJ)", num(at(p, "energy_mJ"))});
    const nlohmann::json& time = at(report, "build_time_s");
    if (at(time, "total").is_number())
        plan.table.rows.push_back({"build time (s)", num(time["total"])});
    const nlohmann::json& settings = at(job, "plan");
    if (settings.is_object())
        for (const auto& [key, value] : settings.items())
            if (key != "strategy") plan.table.rows.push_back({humanKey(key), humanValue(value)});
    const std::string strategy =
        at(p, "strategy").is_string() ? p["strategy"].get<std::string>() : "";
    addRows(plan.table, at(report, strategy.c_str()));
    out.push_back(plan);
    return out;
}

SummaryTable verdictTable(const nlohmann::json& report) {
    SummaryTable t{"Verdict: the cured part against the model", {{"", ""}, {}}};
    auto& rows = t.table.rows;
    rows.push_back({"volume IoU", num(at(report, "iou"))});
    const nlohmann::json& d = at(report, "surface_deviation_mm");
    rows.push_back({"surface deviation (µm)", "mean " + num(at(d, "mean"), 1000) + ", RMS " +
                                                  num(at(d, "rms"), 1000) + ", 95th percentile " +
                                                  num(at(d, "p95"), 1000) + ", max " +
                                                  num(at(d, "max"), 1000)});
    const double samples = at(d, "samples").is_number() ? d["samples"].get<double>() : 0;
    if (samples > 0 && at(d, "beyond_band").is_number())
        rows.push_back({"surface beyond the level set's band",
                        formatNumber(100 * d["beyond_band"].get<double>() / samples, 3) + "%"});
    const nlohmann::json& scale = at(at(report, "report"), "deviation_scale");
    if (scale.is_object())
        rows.push_back({"surface beyond the maps' deviation scale",
                        num(at(scale, "beyond_fraction"), 100, "%") + " beyond ±" +
                            num(at(scale, "limit_um")) + " µm"});
    rows.push_back({"over-cure below down-facing surfaces (µm, median)",
                    num(at(report, "overcure_below_downfacing_mm"), 1000)});
    const nlohmann::json& v = at(report, "validation");
    const nlohmann::json& xy = at(v, "xy_contour_error_mm");
    rows.push_back({"XY contour error (µm)",
                    "mean " + num(at(xy, "mean"), 1000) + ", max " + num(at(xy, "max"), 1000)});
    rows.push_back({"part / cured volume (mm³)", num(at(at(report, "part"), "volume_mm3")) + " / " +
                                                     num(at(report, "cured_volume_mm3"))});
    return t;
}

SummaryTable featuresTable(const nlohmann::json& report) {
    SummaryTable t{"Features (mm)",
                   {{"feature", "predicted", "objective", "measured (mean)",
                     "predicted - objective", "predicted - measured"},
                    {}}};
    for (const nlohmann::json& f : at(report, "features")) {
        std::string measured;
        if (at(f, "measured_mm").is_array() && !f["measured_mm"].empty()) {
            double mean = 0;
            for (const auto& m : f["measured_mm"]) mean += m.get<double>();
            measured = formatNumber(mean / double(f["measured_mm"].size()), 4);
        }
        t.table.rows.push_back({humanValue(at(f, "name")) + " (" + humanValue(at(f, "kind")) + ")",
                                num(at(f, "simulated_mm")), num(at(f, "objective_mm")), measured,
                                num(at(f, "simulated_minus_objective_mm")),
                                num(at(f, "simulated_minus_measured_mm"))});
    }
    return t;
}

ReportTable sideBySide(const std::vector<ReportTable>& tables,
                       const std::vector<std::string>& runNames) {
    ReportTable out;
    out.header.push_back("");
    for (const std::string& name : runNames) out.header.push_back(name);
    std::map<std::string, size_t> rowOf;
    for (size_t run = 0; run < tables.size(); ++run)
        for (const auto& cells : tables[run].rows) {
            if (cells.empty()) continue;
            // Multi-column tables (features) keep their columns joined in one cell per run.
            std::string value;
            for (size_t c = 1; c < cells.size(); ++c) value += (c > 1 ? " | " : "") + cells[c];
            auto [it, added] = rowOf.emplace(cells[0], out.rows.size());
            if (added) {
                out.rows.push_back(std::vector<std::string>(runNames.size() + 1));
                out.rows.back()[0] = cells[0];
            }
            out.rows[it->second][run + 1] = value;
        }
    return out;
}

std::string tableHtml(const ReportTable& table) {
    std::string html = "<table>";
    bool header = false;
    for (const std::string& cell : table.header) header = header || !cell.empty();
    if (header) {
        html += "<tr>";
        for (const std::string& cell : table.header) html += "<th>" + htmlEscape(cell) + "</th>";
        html += "</tr>";
    }
    html += "\n";
    for (const auto& cells : table.rows) {
        html += "<tr>";
        for (size_t i = 0; i < cells.size(); ++i)
            html +=
                (i == 0 ? "<th>" : "<td>") + htmlEscape(cells[i]) + (i == 0 ? "</th>" : "</td>");
        html += "</tr>\n";
    }
    return html + "</table>\n";
}

}  // namespace vpsim::report
