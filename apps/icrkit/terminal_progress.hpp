#pragma once
// The command's progress display: library progress callbacks drawn as one
// line on stderr, only when that is a terminal.

#include <icrkit/core/progress.hpp>

#include <memory>
#include <string>

namespace icrkit::app {

/// Draws a one-line bar on stderr, at most every 100 ms, only when stderr is a
/// terminal and `enabled` is true; finish() clears the line.
class TerminalProgress {
public:
  explicit TerminalProgress(bool enabled);
  ~TerminalProgress();
  TerminalProgress(const TerminalProgress&) = delete;
  TerminalProgress& operator=(const TerminalProgress&) = delete;

  bool active() const { return active_; }
  ProgressCallback callback();
  void finish();

private:
  void report(const std::string& stage, std::size_t done, std::size_t total);
  bool active_;
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace icrkit::app
