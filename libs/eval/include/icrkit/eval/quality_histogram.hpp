#pragma once
/// \file
/// Fig. 8: cumulative histograms of the region quality Q_n = d2 / d1 on raw
/// and filtered meshes (the figures themselves: icrkit/report/quality_plot.hpp).
///
/// Bars. For t = 1.0, 0.9, ..., 0.0 the bar at t is the percentage of regions
/// whose Q_n >= t, among all regions of evaluated grasps (all datasets, one
/// finger count) on that mesh type that have a defined Q_n. A last bar "<0"
/// is the percentage with Q_n < 0 (the central point mapped outside the CAD
/// region), so that the bars at 0.0 and "<0" add up to 100 %. Regions with
/// an undefined Q_n (degenerate, d1 = 0) are not in the percentages; they are
/// counted in `undefined`.

#include <icrkit/eval/experiment_records.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace icrkit::eval {

/// The bars of one mesh type.
struct QualityHistogramSeries {
  /// One per threshold, then one for "<0": regions with Q_n >= t (Q_n < 0 for the last).
  std::vector<std::size_t> counts;
  /// The same as percentages of `regions`; all 0 when `regions` is 0.
  std::vector<double> percent;
  std::size_t regions = 0;    ///< regions with a defined Q_n (the 100 %)
  std::size_t undefined = 0;  ///< regions without Q_n (d1 = 0), left out
};

struct QualityHistogram {
  std::size_t fingers = 0;          ///< 0: every finger count together
  std::size_t evaluated_grasps = 0;
  std::vector<double> thresholds;   ///< 1.0, 0.9, ..., 0.0 (k / 10 exactly as computed)
  std::vector<std::string> labels;  ///< "1.0", ..., "0.0", "<0": one per bar
  QualityHistogramSeries raw;
  QualityHistogramSeries filtered;
};

/// Over all datasets' evaluated grasps with `fingers` fingers (0: all).
QualityHistogram cumulativeQualityHistogram(const std::vector<GraspRecord>& records, std::size_t fingers);

/// {"fingers", "evaluated_grasps", "labels", "thresholds", "raw": {...}, "filtered": {...}}.
std::string qualityHistogramJson(const QualityHistogram& histogram);
/// Atomic writer of the JSON form.
void writeQualityHistogramJson(const std::string& path, const QualityHistogram& histogram);

}  // namespace icrkit::eval
