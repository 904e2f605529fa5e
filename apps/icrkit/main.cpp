// icrkit: Independent Contact Regions on objects reconstructed from noisy
// range data. This file only wires the subcommands and maps failures to the
// documented exit codes: 0 success, 2 bad input or usage, 1 internal error.

#include "commands.hpp"

#include <icrkit/core/error.hpp>

#include <tbb/global_control.h>

#include <exception>
#include <iostream>
#include <memory>

int main(int argc, char** argv) {
  using namespace icrkit::app;
  CLI::App app{"icrkit: Independent Contact Regions on objects reconstructed from noisy range data"};
  app.require_subcommand(1);
  // Global flags may also follow the subcommand: `icrkit info FILE --json`.
  app.fallthrough();
  GlobalOptions options;
  app.add_flag("-q,--quiet", options.quiet, "No messages or progress on stderr");
  app.add_flag("--json", options.json, "Print one JSON summary object on stdout");
  app.add_option("--threads", options.threads, "Worker threads (0 = all cores)")->check(CLI::NonNegativeNumber);

  CommandRunner runner;
  addInfoCommand(app, runner);
  addConvertCommand(app, runner);
  addIcrCommand(app, runner);
  addGraspsCommand(app, runner);
  addSmoothCommand(app, runner);
  addMeshCommand(app, runner);
  addSimulateCommand(app, runner);
  addDatasetsCommand(app, runner);
  addCalibrateCommand(app, runner);
  addReconstructCommand(app, runner);
  addCalibrateRangeCommand(app, runner);
  addEvaluateCommand(app, runner);
  addMergeCommand(app, runner);
  addPaperCommand(app, runner);
  addSensitivityCommand(app, runner);
  addRenderCommand(app, runner);
  addReportCommand(app, runner);
  addPlanCommand(app, runner);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "icrkit: " << e.what() << " (see --help)\n";
    return 2;
  }

  CommandContext context(options);
  try {
    std::unique_ptr<tbb::global_control> thread_limit;
    if (options.threads > 0)
      thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                           static_cast<std::size_t>(options.threads));
    runner(context);
    return 0;
  } catch (const icrkit::InputError& e) {
    std::cerr << "icrkit: " << context.namingFlags(e).what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "icrkit: internal error: " << e.what() << '\n';
    return 1;
  }
}
