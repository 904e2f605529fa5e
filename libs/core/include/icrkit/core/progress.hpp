#pragma once
/// \file
/// Progress of long work, reported through a callback so that libraries stay
/// silent; the `icrkit` command draws it on stderr when that is a terminal.

#include <cstddef>
#include <functional>
#include <memory>
#include <string>

namespace icrkit {

/// Called with a stage name, work done and total work (total 0 = unknown).
/// May be called from several threads; implementations must be thread-safe.
using ProgressCallback = std::function<void(const std::string& stage, std::size_t done, std::size_t total)>;

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

}  // namespace icrkit
