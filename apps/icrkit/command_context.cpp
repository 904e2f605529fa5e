#include "command_context.hpp"

#include <icrkit/core/atomic_file.hpp>

#include <filesystem>

#include <iostream>

namespace icrkit::app {
namespace {

void printHuman(const nlohmann::json& value, const std::string& prefix) {
  for (auto it = value.begin(); it != value.end(); ++it) {
    const std::string key = prefix.empty() ? it.key() : prefix + "." + it.key();
    if (it->is_object())
      printHuman(*it, key);
    else
      std::cout << key << ": " << (it->is_string() ? it->get<std::string>() : it->dump()) << '\n';
  }
}

}  // namespace

CommandContext::CommandContext(const GlobalOptions& options)
    : options_(options), progress_(!options.quiet), start_(std::chrono::steady_clock::now()) {}

void CommandContext::mapFields(std::initializer_list<std::pair<const std::string, std::string>> fields) {
  flags_.insert(fields.begin(), fields.end());
}

InputError CommandContext::namingFlags(const InputError& error) const {
  const auto it = flags_.find(error.source());
  return it == flags_.end() ? error : InputError(it->second, error.location(), error.detail());
}

void CommandContext::note(const std::string& message) const {
  if (!options_.quiet) std::cerr << message << '\n';
}

double CommandContext::elapsedMs() const {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
}

void CommandContext::emit(const nlohmann::json& summary) {
  progress_.finish();
  if (options_.json)
    std::cout << summary.dump() << '\n';
  else
    printHuman(summary, "");
  std::cout.flush();
}

std::string summaryPathFor(const std::string& output) {
  return std::filesystem::path(output).replace_extension(".json").string();
}

void writeSummaryFile(const std::string& path, const nlohmann::json& summary) {
  const std::string text = summary.dump() + "\n";
  writeFileAtomically(path, [&text](std::ostream& out) { out << text; }, false);
}

}  // namespace icrkit::app
