#pragma once
// The subcommands behind `daisy`. Each command's file registers it with one function: the
// subcommand, its options (the common ones included) and what runs when it is chosen. A run
// returns the process exit status, any message already printed (0 done, 2 bad usage or bad
// input, 1 any other failure), or an Error, which main() prints as one line and turns into
// exit status 2; main() turns an exception that escapes a run into exit status 1.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/options.h"
#include "core/expected.h"

namespace daisy::app {

// What main() shares with the commands it registers.
struct CommandContext {
    using Run = std::function<Expected<int>()>;
    struct Command {
        CLI::App* subcommand;
        Run run;
    };

    // Parsed into by every subcommand (only one runs); main() finishes them after parsing.
    CommonOptions common;
    std::vector<Command> commands;

    // Adds a subcommand with the common options; `sceneRequired`: its SCENE argument is.
    CLI::App* add(CLI::App& app, const std::string& name, const std::string& description,
                  bool sceneRequired = true);
    // What runs when `subcommand` is the one chosen.
    void onRun(CLI::App* subcommand, Run run);
};

// In the order of `daisy --help`.
void addRenderCommand(CLI::App& app, CommandContext& context);
void addSolveCommand(CLI::App& app, CommandContext& context);
void addFormFactorsCommand(CLI::App& app, CommandContext& context);
void addInfoCommand(CLI::App& app, CommandContext& context);
void addViewCommand(CLI::App& app, CommandContext& context);
void addValidateCommand(CLI::App& app, CommandContext& context);
void addBenchCommand(CLI::App& app, CommandContext& context);

// `daisy cache list|clear|prune [--cache DIR] [--cache-size N]` (docs/cache.md).
void addCacheCommand(CLI::App& app, CommandContext& context);

// For subcommands whose stage has not landed: says so on stderr and returns 2.
int notBuiltYet(const char* command, const char* stage);

}  // namespace daisy::app
