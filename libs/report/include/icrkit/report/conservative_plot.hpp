#pragma once
/// \file
/// The conservative-growth summary (eval::ConservativeSummary) as a Markdown
/// table and as the Int-vs-FP curve over K (SVG; patch rows as separate
/// points), and the writer of a run's conservative.{json,md,svg}.

#include <icrkit/eval/conservative_summary.hpp>

#include <string>
#include <vector>

namespace icrkit::report {

std::string conservativeSummaryMarkdown(const eval::ConservativeSummary& summary);
/// Median Int against median FP of the pooled rows, one polyline per mesh
/// type, each point labelled with its K (plain growth as "plain").
std::string conservativeCurveSvg(const eval::ConservativeSummary& summary);

/// Writes conservative.json, conservative.md and conservative.svg into
/// `directory` (atomically) and returns their paths.
std::vector<std::string> writeConservativeSummary(const std::string& directory, const eval::ConservativeSummary& summary);

}  // namespace icrkit::report
