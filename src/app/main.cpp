// `daisy`: parse the command line, run the chosen subcommand, turn its outcome into the exit
// status (DESIGN.md section 9). The subcommands register themselves from their own files
// (commands.h).
#include <cstdio>
#include <exception>
#include <string>

#include "app/commands.h"
#include "core/interrupt.h"
#include "core/log.h"
#include "pipeline/backend_registry.h"

namespace daisy::app {

CLI::App* CommandContext::add(CLI::App& app, const std::string& name,
                              const std::string& description, bool sceneRequired) {
    CLI::App* subcommand = app.add_subcommand(name, description);
    addCommonOptions(*subcommand, common, sceneRequired);
    return subcommand;
}

void CommandContext::onRun(CLI::App* subcommand, Run run) {
    commands.push_back({subcommand, std::move(run)});
}

}  // namespace daisy::app

namespace {

using namespace daisy::app;

// Every subcommand, in the order `daisy --help` lists them.
void (*const kCommands[])(CLI::App&, CommandContext&) = {
    addRenderCommand, addSolveCommand,    addFormFactorsCommand, addInfoCommand,
    addViewCommand,   addValidateCommand, addBenchCommand,       addCacheCommand};

// "render, solve, ... or bench".
std::string commandNames(const CommandContext& context) {
    std::string names;
    for (std::size_t k = 0; k < context.commands.size(); ++k) {
        if (k > 0) names += k + 1 == context.commands.size() ? " or " : ", ";
        names += context.commands[k].subcommand->get_name();
    }
    return names;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"DaisyRiot: spectral radiosity with fluorescent materials", "daisy"};
    app.require_subcommand(1);
    std::string version = "daisy 0.1.0 (backends:";
    for (const std::string& name : daisy::builtInBackendNames())
        version += " " + name;
    version += ")";
    app.set_version_flag("--version", version);
    CommandContext context;
    for (const auto add : kCommands)
        add(app, context);

    const std::string first = argc > 1 ? argv[1] : "";
    if (!first.empty() && first[0] != '-' &&
        app.get_subcommands([&](CLI::App* sub) { return sub->check_name(first); }).empty()) {
        std::fprintf(stderr, "error: unknown command '%s' (expected %s; see daisy --help)\n",
                     first.c_str(), commandNames(context).c_str());
        return 2;
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "error: %s (see daisy --help)\n", e.what());
        return 2;
    }

    // SIGINT / SIGTERM: temporaries removed, one line, exit 130 (core/interrupt.h).
    daisy::installInterruptHandlers();
    finishCommonOptions(context.common);
    daisy::setVerbosity(context.common.quiet         ? daisy::Verbosity::Quiet
                            : context.common.verbose ? daisy::Verbosity::Verbose
                                                     : daisy::Verbosity::Normal);
    for (const CommandContext::Command& command : context.commands) {
        if (!*command.subcommand) continue;
        try {
            daisy::Expected<int> status = command.run();
            if (!status) {
                // A stage that stopped for SIGINT / SIGTERM returns its own "interrupted" error,
                // and may do so before the watchdog has printed its line: the one line only.
                if (daisy::interruptSignal() != 0) daisy::exitInterrupted();
                daisy::logError(status.error().message);
                return 2;
            }
            return *status;
        } catch (const std::exception& e) {
            daisy::logError(e.what());
            return 1;
        }
    }
    return 1;
}
