#include <icrkit/ndt/preselection_record.hpp>

#include <nlohmann/json.hpp>

namespace icrkit::ndt {

std::string preselectionRecordJson(const PreselectionReport& s, bool given_cardinality, bool given_flatness) {
  const bool none = s.rule == PreselectionRule::None;
  const char* source = s.rule == PreselectionRule::PaperMean ? "mean" : "robust";
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
  const nlohmann::json record{{"rule", preselectionRuleName(s.rule)},
                              {"thresholds", thresholds},
                              {"excluded", excluded},
                              {"statistics",
                               {{"points", s.points},
                                {"mean_cardinality", s.mean_cardinality},
                                {"mean_flatness", s.mean_flatness},
                                {"median_cardinality", s.median_cardinality},
                                {"median_flatness", s.median_flatness},
                                {"log_flatness_spread", s.log_flatness_spread}}}};
  return record.dump();
}

}  // namespace icrkit::ndt
