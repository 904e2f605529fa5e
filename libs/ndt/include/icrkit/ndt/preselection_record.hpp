#pragma once
/// \file
/// What a preselection rule did, as the JSON object the commands' summaries
/// and reconstruction.json carry (docs/formats.md).

#include <icrkit/ndt/preselection.hpp>

#include <string>

namespace icrkit::ndt {

/// {"rule", "thresholds": {cardinality, cardinality_source, flatness,
/// flatness_source} or null, "excluded": {total, percent, cardinality_only,
/// flatness_only, both} or null, "statistics": {...}} as JSON text (keys
/// sorted). A threshold's source is "given" when `given_*`, else "mean"
/// (rule paper-mean) or "robust"; rule none has no thresholds or exclusions.
std::string preselectionRecordJson(const PreselectionReport& summary, bool given_cardinality = false,
                                   bool given_flatness = false);

}  // namespace icrkit::ndt
