#include "preselection_options.hpp"

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

nlohmann::json preselectionJson(const ndt::PreselectionSummary& s, bool given_cardinality, bool given_flatness) {
  const bool none = s.rule == ndt::PreselectionRule::None;
  const char* source = s.rule == ndt::PreselectionRule::PaperMean ? "mean" : "robust";
  nlohmann::json thresholds = nullptr, excluded = nullptr;
  if (!none) {
    thresholds = {{"cardinality", s.cardinality_threshold},
                  {"cardinality_source", given_cardinality ? "given" : source},
                  {"flatness", s.flatness_threshold},
                  {"flatness_source", given_flatness ? "given" : source}};
    excluded = {{"total", s.excluded},
                {"percent", s.points ? 100.0 * static_cast<double>(s.excluded) / static_cast<double>(s.points) : 0.0},
                {"cardinality_only", s.excluded_cardinality_only},
                {"flatness_only", s.excluded_flatness_only},
                {"both", s.excluded_both}};
  }
  return {{"rule", ndt::preselectionRuleName(s.rule)},
          {"thresholds", thresholds},
          {"excluded", excluded},
          {"statistics",
           {{"points", s.points},
            {"mean_cardinality", s.mean_cardinality},
            {"mean_flatness", s.mean_flatness},
            {"median_cardinality", s.median_cardinality},
            {"median_flatness", s.median_flatness},
            {"log_flatness_spread", s.log_flatness_spread}}}};
}

}  // namespace icrkit::app
