#pragma once
// What every subcommand shares: the global flags, the JSON summary and the
// progress display. Commands only call libraries and report.

#include "terminal_progress.hpp"

#include <icrkit/core/error.hpp>

#include <nlohmann/json.hpp>

#include <chrono>
#include <map>
#include <string>

namespace icrkit::app {

struct GlobalOptions {
  bool quiet = false;  ///< no human-readable messages or progress on stderr
  bool json = false;   ///< one JSON object on stdout, nothing else there
  int threads = 0;     ///< 0 = all cores
};

class CommandContext {
public:
  explicit CommandContext(const GlobalOptions& options);

  const GlobalOptions& options() const { return options_; }
  /// A progress callback (empty when quiet, JSON-only or not a terminal).
  ProgressCallback progress() { return progress_.callback(); }
  /// A human-readable note on stderr unless --quiet (an empty one is none).
  void note(const std::string& message) const;
  /// Milliseconds since the command started.
  double elapsedMs() const;
  /// Prints the summary: as JSON with --json, else as "key: value" lines.
  void emit(const nlohmann::json& summary);
  /// Libraries name the parameter a bad value came from by its field
  /// (`SmoothingParameters::passes`); the command says which of its flags
  /// sets that field, so that the user reads the flag.
  void mapFields(std::initializer_list<std::pair<const std::string, std::string>> fields);
  /// `error` with its source, and every mapped field its message names,
  /// replaced by the flag mapped to it.
  InputError namingFlags(const InputError& error) const;

private:
  GlobalOptions options_;
  TerminalProgress progress_;
  std::chrono::steady_clock::time_point start_;
  std::map<std::string, std::string> flags_;
};

/// Where a command's JSON summary goes: `output` with the extension .json.
std::string summaryPathFor(const std::string& output);
/// Writes `summary` (one line of JSON) atomically to `path`.
void writeSummaryFile(const std::string& path, const nlohmann::json& summary);

/// An output folder: InputError naming it when it exists and is not a directory.
void requireOutputFolder(const std::string& output);

}  // namespace icrkit::app
