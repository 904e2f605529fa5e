#include "command_context.hpp"

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/elapsed.hpp>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <vector>

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
  const std::string& source = it == flags_.end() ? error.source() : it->second;
  // A message may point to other fields too ("give ReconstructionParameters::
  // pose_file"): the longest names first, so that no name's prefix wins.
  std::vector<const std::pair<const std::string, std::string>*> by_length;
  for (const auto& entry : flags_) by_length.push_back(&entry);
  std::stable_sort(by_length.begin(), by_length.end(),
                   [](const auto* a, const auto* b) { return a->first.size() > b->first.size(); });
  std::string detail = error.detail();
  for (const auto* entry : by_length)
    for (std::size_t at = detail.find(entry->first); at != std::string::npos;
         at = detail.find(entry->first, at + entry->second.size()))
      detail.replace(at, entry->first.size(), entry->second);
  if (source == error.source() && detail == error.detail()) return error;
  return InputError(source, error.location(), detail);
}

void CommandContext::note(const std::string& message) const {
  if (!options_.quiet && !message.empty()) std::cerr << message << '\n';
}

double CommandContext::elapsedMs() const {
  return millisecondsSince(start_);
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

void requireOutputFolder(const std::string& output) {
  std::error_code error;
  if (std::filesystem::exists(output, error) && !std::filesystem::is_directory(output, error))
    throw InputError(output, "", "exists and is not a directory");
}

}  // namespace icrkit::app
