#include "terminal_progress.hpp"

#include <chrono>
#include <cstdio>
#include <mutex>
#include <unistd.h>

namespace icrkit::app {

struct TerminalProgress::State {
  std::mutex mutex;
  std::chrono::steady_clock::time_point last_draw{};
  bool drawn = false;
};

TerminalProgress::TerminalProgress(bool enabled)
    : active_(enabled && ::isatty(STDERR_FILENO) == 1), state_(std::make_unique<State>()) {}

TerminalProgress::~TerminalProgress() { finish(); }

ProgressCallback TerminalProgress::callback() {
  if (!active_) return {};
  return [this](const std::string& stage, std::size_t done, std::size_t total) { report(stage, done, total); };
}

void TerminalProgress::report(const std::string& stage, std::size_t done, std::size_t total) {
  std::lock_guard<std::mutex> lock(state_->mutex);
  const auto now = std::chrono::steady_clock::now();
  const bool complete = total > 0 && done >= total;
  if (state_->drawn && !complete && now - state_->last_draw < std::chrono::milliseconds(100)) return;
  state_->last_draw = now;
  state_->drawn = true;
  if (total > 0) {
    constexpr int width = 30;
    const double fraction = static_cast<double>(done) / static_cast<double>(total);
    const int filled = static_cast<int>(fraction * width);
    std::fprintf(stderr, "\r\033[K%s [%.*s%*s] %3.0f%%", stage.c_str(), filled, "##############################",
                 width - filled, "", 100.0 * fraction);
  } else {
    std::fprintf(stderr, "\r\033[K%s %zu", stage.c_str(), done);
  }
  std::fflush(stderr);
}

void TerminalProgress::finish() {
  if (!active_ || !state_) return;
  std::lock_guard<std::mutex> lock(state_->mutex);
  if (state_->drawn) {
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
    state_->drawn = false;
  }
}

}  // namespace icrkit::app
