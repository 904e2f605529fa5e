#include "preselection_options.hpp"

#include <icrkit/ndt/preselection_record.hpp>

namespace icrkit::app {

CLI::Option* addPreselectionOption(CLI::App& command, std::string& name, const std::string& what) {
  return command
      .add_option("--preselection", name,
                  "Preselection rule " + what +
                      ": default (exclude isolated points and windows far less flat than the cloud's noise "
                      "makes them; robust statistics), paper-mean (the paper's literal rule: below the mean "
                      "cardinality or flatness) or none (docs/smoothing.md)")
      ->check(CLI::IsMember({"default", "robust", "paper-mean", "none"}))
      ->capture_default_str();
}

nlohmann::json preselectionJson(const ndt::PreselectionReport& s, bool given_cardinality, bool given_flatness) {
  return nlohmann::json::parse(ndt::preselectionRecordJson(s, given_cardinality, given_flatness));
}

}  // namespace icrkit::app
