// JobEstimate's sums, its JSON and table forms, and the refusal of a job that does not fit.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "vpsim/core/error.h"
#include "vpsim/core/resources.h"
#include "vpsim/core/text.h"
#include "vpsim/pipeline/estimate.h"

namespace vpsim::pipeline {
namespace {

constexpr Stage STAGES[] = {Stage::Part,   Stage::Kernel, Stage::Slice,   Stage::Plan,
                            Stage::Expose, Stage::Cure,   Stage::Validate};

bool alive(const EstimateItem& item, Stage stage) {
    return int(item.first) <= int(stage) && int(stage) <= int(item.last);
}

/// The items alive in `stage`, largest first.
std::vector<const EstimateItem*> itemsAt(const JobEstimate& e, Stage stage) {
    std::vector<const EstimateItem*> out;
    for (const EstimateItem& item : e.items)
        if (alive(item, stage)) out.push_back(&item);
    std::sort(out.begin(), out.end(),
              [](const EstimateItem* a, const EstimateItem* b) { return a->bytes > b->bytes; });
    return out;
}

std::string padded(std::string text, size_t width) {
    if (text.size() < width) text.append(width - text.size(), ' ');
    return text + " ";
}

}  // namespace

const char* stageName(Stage stage) {
    static const char* names[] = {"part", "kernel", "slice", "plan", "expose", "cure", "validate"};
    return names[int(stage)];
}

double JobEstimate::bytesAt(Stage stage) const {
    double sum = 0;
    for (const EstimateItem& item : items)
        if (alive(item, stage)) sum += item.bytes;
    return sum;
}

Stage JobEstimate::peakStage() const {
    Stage best = Stage::Part;
    for (Stage s : STAGES)
        if (bytesAt(s) > bytesAt(best)) best = s;
    return best;
}

double JobEstimate::outputBytes() const {
    double sum = 0;
    for (const OutputEstimate& o : outputs) sum += o.bytes;
    return sum;
}

double JobEstimate::seconds() const {
    double sum = 0;
    for (const auto& [stage, s] : stageSeconds) sum += s;
    return sum;
}

nlohmann::json JobEstimate::toJson(const RunContext& context) const {
    nlohmann::json memory = nlohmann::json::array(), files = nlohmann::json::array();
    for (const EstimateItem& item : items)
        memory.push_back({{"name", item.name},
                          {"bytes", item.bytes},
                          {"stages", {stageName(item.first), stageName(item.last)}},
                          {"detail", item.detail}});
    for (const OutputEstimate& o : outputs) files.push_back({{"file", o.file}, {"bytes", o.bytes}});
    nlohmann::json stages = nlohmann::json::object(), seconds = nlohmann::json::object();
    for (Stage s : STAGES) stages[stageName(s)] = bytesAt(s);
    for (const auto& [stage, s] : stageSeconds) seconds[stage] = s;
    return {{"job", job},
            {"plan_only", planOnly},
            {"peak_bytes", peakBytes()},
            {"peak_stage", stageName(peakStage())},
            {"budget_bytes", double(memoryBudget(context))},
            {"bytes_by_stage", stages},
            {"memory", memory},
            {"outputs", files},
            {"output_bytes", outputBytes()},
            {"seconds", this->seconds()},
            {"stage_seconds", seconds},
            {"figures", figures},
            {"tiles",
             {{"side_mm", tileSide},
              {"count", tileCount},
              {"bytes_per_tile", tileBytes},
              {"checkpointed", checkpointed}}}};
}

std::string JobEstimate::table(const RunContext& context) const {
    std::ostringstream out;
    out << "estimate of " << job << (planOnly ? " (vpsim plan)" : "") << ": peak "
        << formatBytes(peakBytes()) << " in the " << stageName(peakStage()) << " stage (budget "
        << formatBytes(double(memoryBudget(context))) << "), " << formatBytes(outputBytes())
        << " of files, about " << formatNumber(seconds(), 2) << " s\n";
    if (!planOnly)
        out << (tileCount > 1
                    ? "tiles: " + std::to_string(tileCount) + " x-y tiles of " +
                          formatNumber(tileSide, 4) +
                          " mm (and a halo), one after "
                          "another, " +
                          formatBytes(tileBytes) + " per tile" +
                          (checkpointed ? "; a checkpoint after each (--resume)" : "") + "\n"
                    : std::string("tiles: one (the whole grid)\n"));
    out << "\nmemory\n";
    for (const EstimateItem& item : items)
        out << "  " << padded(item.name, 40) << padded(formatBytes(item.bytes), 10)
            << padded(std::string(stageName(item.first)) + ".." + stageName(item.last), 16)
            << item.detail << "\n";
    out << "  " << padded("by stage", 40);
    for (Stage s : STAGES)
        if (!planOnly || int(s) <= int(Stage::Plan))
            out << stageName(s) << " " << formatBytes(bytesAt(s)) << "  ";
    out << "\n\nfiles\n";
    for (const OutputEstimate& o : outputs)
        out << "  " << padded(o.file, 40) << formatBytes(o.bytes) << "\n";
    out << "\ntime (rough, 2 cores)\n";
    for (const auto& [stage, s] : stageSeconds)
        out << "  " << padded(stage, 40) << formatNumber(s, 2) << " s\n";
    return out.str();
}

void checkEstimate(const JobEstimate& e, const RunContext& context) {
    const double budget = double(memoryBudget(context));
    const Stage peak = e.peakStage();
    const double bytes = e.bytesAt(peak);
    if (bytes <= budget) return;
    std::string parts, hint;
    int shown = 0;
    for (const EstimateItem* item : itemsAt(e, peak)) {
        if (shown == 2 || item->bytes < 0.05 * bytes) break;
        parts += std::string(shown++ ? "; " : "") + item->name + " " + formatBytes(item->bytes) +
                 " (" + item->detail + ")";
        if (hint.empty()) hint = item->hint;
    }
    throw ResourceError("job '" + e.job + "' would need " + formatBytes(bytes) +
                        " at its peak (the " + stageName(peak) + " stage): " + parts +
                        "; more than the " + formatBytes(budget) + " allowed (" +
                        memoryBudgetOrigin(context) + "): use " +
                        (hint.empty() ? std::string("a smaller job") : hint) +
                        " (--dry-run prints the whole estimate)");
}

void checkDisk(const JobEstimate& e, const std::string& outDir) {
    std::filesystem::path dir = std::filesystem::absolute(outDir);
    while (!std::filesystem::exists(dir) && dir.has_parent_path() && dir != dir.parent_path())
        dir = dir.parent_path();
    std::error_code error;
    const std::filesystem::space_info space = std::filesystem::space(dir, error);
    if (error) return;  // nothing to judge by: the writes report their own failure
    const double needed = e.outputBytes();
    if (needed <= double(space.available)) return;
    throw ResourceError("job '" + e.job + "' would write " + formatBytes(needed) + " into " +
                        outDir + ", more than the " + formatBytes(double(space.available)) +
                        " free there (tiles do not shrink files): write fewer outputs or a "
                        "smaller job (--dry-run prints the files' sizes)");
}

}  // namespace vpsim::pipeline
