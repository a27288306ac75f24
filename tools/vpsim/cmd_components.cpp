// `vpsim components`: every registered planner, cure law and exporter with its key table (name,
// kind, dimension, default, range, doc), as text, JSON or the Markdown of examples/README.md.
#include <iostream>

#include "commands.h"
#include "vpsim/pipeline/builtins.h"

namespace {

struct ComponentsOptions {
    bool json = false, markdown = false;
};

void componentsCommand(const ComponentsOptions& options) {
    using namespace vpsim;
    const pipeline::Builtins builtins = pipeline::makeBuiltins();
    if (options.markdown) {
        std::cout << pipeline::componentsMarkdown(builtins);
        return;
    }
    const nlohmann::json all = pipeline::componentsJson(builtins);
    if (options.json) return cli::printJson(all);
    cli::printComponents(all["planners"], "plan");
    cli::printComponents(all["cure_laws"], "cure");
    cli::printComponents(all["exporters"], "export.NAME");
}

vpsim::cli::CommandRegistration registerComponents{
    "components", [](CLI::App& app, const vpsim::cli::Globals&) {
        auto* command = app.add_subcommand(
            "components", "list the planners, cure laws and exporters with their keys");
        auto options = std::make_shared<ComponentsOptions>();
        command->add_flag("--json", options->json, "print JSON");
        command->add_flag("--markdown", options->markdown,
                          "print the key tables of examples/README.md");
        command->callback([options] { componentsCommand(*options); });
    }};

}  // namespace
