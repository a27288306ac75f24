// `vpsim compare RUN_DIR... --out DIR`: runs side by side on one page (report/compare_page.h).
#include <iostream>

#include "commands.h"
#include "vpsim/report/compare_page.h"

namespace {

struct CompareOptions {
    std::vector<std::string> runs;
    std::string out;
};

vpsim::cli::CommandRegistration registerCompare{
    "compare", [](CLI::App& app, const vpsim::cli::Globals&) {
        auto* command =
            app.add_subcommand("compare",
                               "put runs side by side: inputs, verdicts, features, figures and "
                               "exposure-error curves in columns on one page (DIR/index.html)");
        auto options = std::make_shared<CompareOptions>();
        command->add_option("runs", options->runs, "run directories (from vpsim run)")->required();
        command->add_option("--out", options->out, "output directory")->required();
        command->callback([options] {
            const std::string page = vpsim::report::writeComparePage(options->runs, options->out);
            std::cout << "vpsim compare -> " << page << "\n";
        });
    }};

}  // namespace
