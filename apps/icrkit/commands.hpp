#pragma once
// Registration of the subcommands. Each returns the callback that runs it
// once the command line has been parsed.

#include "command_context.hpp"

#include <CLI/CLI.hpp>

#include <functional>

namespace icrkit::app {

using CommandRunner = std::function<void(CommandContext&)>;

void addInfoCommand(CLI::App& app, CommandRunner& runner);
void addConvertCommand(CLI::App& app, CommandRunner& runner);
void addIcrCommand(CLI::App& app, CommandRunner& runner);
void addGraspsCommand(CLI::App& app, CommandRunner& runner);
void addSmoothCommand(CLI::App& app, CommandRunner& runner);
void addMeshCommand(CLI::App& app, CommandRunner& runner);
void addSimulateCommand(CLI::App& app, CommandRunner& runner);
void addDatasetsCommand(CLI::App& app, CommandRunner& runner);
void addCalibrateCommand(CLI::App& app, CommandRunner& runner);
void addReconstructCommand(CLI::App& app, CommandRunner& runner);
void addCalibrateRangeCommand(CLI::App& app, CommandRunner& runner);
void addEvaluateCommand(CLI::App& app, CommandRunner& runner);
void addMergeCommand(CLI::App& app, CommandRunner& runner);
void addPaperCommand(CLI::App& app, CommandRunner& runner);
void addSensitivityCommand(CLI::App& app, CommandRunner& runner);
void addRenderCommand(CLI::App& app, CommandRunner& runner);
void addReportCommand(CLI::App& app, CommandRunner& runner);
void addPlanCommand(CLI::App& app, CommandRunner& runner);

}  // namespace icrkit::app
