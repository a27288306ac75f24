// `vpsim export plan.json -o scan.cli`: writes a saved scan plan as a machine file. CLI (Common
// Layer Interface) for laser plans, ASCII by default or binary. With --trajectories the layer
// parts are ordered first (plan.order methods) with the scanner of a machine file, otherwise the
// plan's saved trajectories (or its vectors in plan order) are written. Prints the layer and vector
// counts and the build-time estimate (seed 002 Eq. 1-4) with --json.
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/text.h"
#include "vpsim/core/units.h"
#include "vpsim/exporters/export_file.h"
#include "vpsim/pipeline/builtins.h"
#include "vpsim/plan/machine/build_time.h"
#include "vpsim/plan/machine/scan_report.h"
#include "vpsim/plan/machine/trajectory.h"
#include "vpsim/plot/plot.h"

namespace {

using namespace vpsim;

struct ExportCliOptions {
    std::string plan, out = "scan.cli", exporter, format, units, machine, order = "auto", svg;
    std::vector<std::string> options;  ///< KEY=VALUE of the exporter's section
    bool trajectories = false, json = false;
};

/// The exporter's section from --option, --format and --units.
nlohmann::json exporterSection(const ExportCliOptions& o) {
    nlohmann::json section = nlohmann::json::object();
    for (const std::string& assignment : o.options) applyOverride(section, assignment);
    if (!o.format.empty()) section["format"] = o.format;
    if (!o.units.empty()) section["units"] = o.units;
    return section;
}

void runExport(const ExportCliOptions& o, const cli::Globals& globals) {
    plan::ScanPlan scanPlan = plan::loadScanPlan(o.plan);
    plan::BuildTimeOptions timing;
    if (!o.machine.empty()) {
        ConfigNode root = ConfigNode::load(o.machine, globals.overrides);
        const bool wrapped = root.has("machine");  // a job file or {"machine": {...}}
        timing = plan::buildTimeOptionsFromConfig(wrapped ? root.child("machine") : root);
        const nlohmann::json document = loadJsonFile(o.machine);
        if (wrapped)  // the other sections of a job file are not this command's business
            for (const auto& [key, value] : document.items())
                if (key != "machine") root.raw(key);
        root.checkUnknownKeys();
    }
    nlohmann::json order;
    if (o.trajectories) {
        plan::TrajectoryOptions options;
        options.scanner = timing.scanner;
        options.order = plan::parseOrderMethod(o.order, "--order");
        auto trajectories = plan::buildTrajectories(scanPlan, options);
        plan::attachTrajectories(scanPlan, trajectories);
        order = plan::scanOrderJson(trajectories);
        if (!o.svg.empty()) {
            size_t k = plan::busiestLayer(trajectories);
            plan::writeScanPathFigure(plot::figureStem(o.svg), trajectories[k].moves,
                                      "scan path of layer " + std::to_string(k));
        }
    }
    exporters::ExportRequest request;
    request.path = o.out;
    request.exporter = o.exporter;
    request.options = exporterSection(o);
    request.optionsSource = "command line";
    request.hint = "--exporter NAME and its --option KEY=VALUE";
    request.planSource = o.plan;
    request.timing = timing;
    nlohmann::json summary =
        exporters::exportToFile(pipeline::makeBuiltins().exporters, scanPlan, request);
    const std::string name = summary["exporter"];
    const size_t vectors = summary["vectors"];
    const bool dlp = !summary.contains("build_time_s");
    if (!order.is_null()) summary["scan_order"] = order;
    if (o.json)
        cli::printJson(summary);
    else
        std::cout << "wrote " << o.out << " (" << name << "): " << scanPlan.layers.size()
                  << " layers, " << vectors << " vectors"
                  << (dlp ? ""
                          : ", build time " +
                                formatQuantity(summary["build_time_s"]["total"].get<double>()) +
                                " s")
                  << "\n";
}

vpsim::cli::CommandRegistration registerExport{
    "export", [](CLI::App& app, const vpsim::cli::Globals& globals) {
        auto* cmd = app.add_subcommand(
            "export",
            "write a saved scan plan as a machine file (CLI, SL1, ...: vpsim components)");
        auto o = std::make_shared<ExportCliOptions>();
        cmd->add_option("plan", o->plan, "scan plan JSON (vpsim run writes plan.json)")->required();
        cmd->add_option("-o,--out", o->out, "output file (default scan.cli)");
        cmd->add_option("--exporter", o->exporter,
                        "registered exporter (default: by the output's extension)");
        cmd->add_option("--option", o->options,
                        "KEY=VALUE of the exporter's section (repeatable; vpsim components)");
        cmd->add_option("--format", o->format,
                        "shorthand for --option format=... (CLI: ascii or "
                        "binary)");
        cmd->add_option("--units", o->units,
                        "shorthand for --option units=... (CLI: length of one coordinate unit)");
        cmd->add_option("--machine", o->machine,
                        "machine JSON (or a job with a machine section): machine.scanner limits "
                        "and delays, recoat_time, projector_irradiance for the build time");
        cmd->add_flag("--trajectories", o->trajectories,
                      "order the layer parts and build the scan trajectories before writing");
        cmd->add_option("--order", o->order,
                        "with --trajectories: auto (default), exact, heuristic, "
                        "nearest-neighbour, as-sliced");
        cmd->add_option(
            "--svg", o->svg,
            "with --trajectories: write the busiest layer's scan path here (FILE.svg and "
            "FILE.png)");
        cmd->add_flag("--json", o->json,
                      "print {file, exporter, options, layers, vectors, build_time_s, scan_order}");
        cmd->callback([o, &globals] { runExport(*o, globals); });
    }};

}  // namespace
