#pragma once
// `--preselection NAME` as every command that applies a preselection rule
// spells it (smooth, reconstruct, evaluate, paper, sensitivity), and the
// JSON form of what a rule did.

#include <icrkit/ndt/preselection.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <string>

namespace icrkit::app {

/// Adds `--preselection NAME` (default, paper-mean or none) storing into `name`.
CLI::Option* addPreselectionOption(CLI::App& command, std::string& name, const std::string& what);

/// {"rule", "thresholds": {...}, "excluded": {...}, "statistics": {...}};
/// `given_*`: the threshold came from the command line.
nlohmann::json preselectionJson(const ndt::PreselectionReport& summary, bool given_cardinality = false,
                                bool given_flatness = false);

}  // namespace icrkit::app
