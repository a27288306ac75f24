// vpsim command-line program: parses options, calls the library, prints results.
// Subcommands live in cmd_*.cpp and register themselves (commands.h).
#include <cstdlib>
#include <iostream>

#include "commands.h"
#include "vpsim/core/error.h"
#include "vpsim/core/log.h"
#include "vpsim/core/progress.h"
#include "vpsim/core/text.h"

namespace {

/// Any message, whatever it quotes, as one printable line of bounded length.
std::string oneLine(const std::string& message) {
    return vpsim::escaped(message, 1200);
}

/// Numeric options take decimal numbers only: CLI11's conversions would also read "0x10" as 16.
void requireDecimalNumbers(CLI::App& app) {
    const CLI::Validator decimal(
        [](std::string& text) {
            return vpsim::parseDecimal(text)
                       ? std::string()
                       : "expected a decimal number, got " + vpsim::quoteUser(text);
        },
        "", "");
    for (CLI::Option* option : app.get_options()) {
        const std::string type = option->get_type_name();
        if (type == "FLOAT" || type == "INT" || type == "UINT" || type == "NUMBER")
            option->check(decimal);
    }
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
        requireDecimalNumbers(*sub);
}

}  // namespace

int main(int argc, char** argv) {
    using namespace vpsim;
    CLI::App app{
        "vpsim: exposure simulator and process planner for vat photopolymerization "
        "(laser SLA of ceramic slurries and DLP mask projection)"};
    app.set_version_flag("--version", std::string("vpsim ") + VPSIM_VERSION);
    app.require_subcommand(1);
    app.fallthrough();

    cli::Globals globals;
    try {
        globals.readEnvironment();
    } catch (const Error& e) {
        std::cerr << "vpsim: error: " << oneLine(e.what()) << std::endl;
        return 1;
    }
    app.add_option("--backend", globals.backend,
                   "where the physics runs: auto (Vulkan if a device exists, "
                   "else CPU), vulkan, cpu [env VPSIM_BACKEND]")
        ->check(CLI::IsMember({"auto", "vulkan", "cpu"}));
    app.add_option("--device", globals.device,
                   "Vulkan device index or part of its name "
                   "(default: a hardware GPU, else lavapipe) [env VPSIM_DEVICE]");
    app.add_flag("--validate", globals.validation,
                 "run under VK_LAYER_KHRONOS_validation [env VPSIM_VALIDATION=1]");
    app.add_option("--set", globals.overrides,
                   "override a config value, e.g. --set particles.radius=\"2 um\"")
        ->take_all();
    // Flag callbacks run while parsing, before any subcommand callback.
    app.add_flag_callback(
        "-q,--quiet",
        [&globals] {
            globals.quiet = true;
            setLogLevel(LogLevel::Warn);
            Progress::setEnabled(false);
        },
        "no progress display or info messages");
    app.add_flag_callback(
        "-v,--verbose", [] { setLogLevel(LogLevel::Debug); }, "debug messages");

    for (auto& [name, setup] : cli::commandRegistry()) setup(app, globals);
    requireDecimalNumbers(app);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
        std::cerr << "vpsim: error: " << oneLine(e.what()) << " (see vpsim --help)" << std::endl;
        return e.get_exit_code();
    } catch (const Error& e) {
        std::cerr << "vpsim: error: " << oneLine(e.what()) << std::endl;
        globals.abortOtherRanks();
        return 1;
    } catch (const std::bad_alloc&) {
        std::cerr << "vpsim: error: out of memory" << std::endl;
        globals.abortOtherRanks();
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "vpsim: internal error: " << oneLine(e.what()) << std::endl;
        globals.abortOtherRanks();
        return 2;
    }
    return globals.exitStatus;
}
