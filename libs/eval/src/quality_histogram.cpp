#include <icrkit/eval/quality_histogram.hpp>

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/number_text.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace icrkit::eval {
namespace {

using Json = nlohmann::ordered_json;

constexpr int kThresholdSteps = 10;  // t = k / 10 for k = 10 .. 0

void addMesh(QualityHistogramSeries& series, const MeshOutcome& mesh, const std::vector<double>& thresholds) {
  for (const auto& region : mesh.regions) {
    if (!region.quality || std::isnan(*region.quality)) {
      ++series.undefined;
      continue;
    }
    const double q = *region.quality;
    ++series.regions;
    for (std::size_t i = 0; i < thresholds.size(); ++i)
      if (q >= thresholds[i]) ++series.counts[i];
    if (q < 0.0) ++series.counts.back();
  }
}

void finishPercent(QualityHistogramSeries& series) {
  series.percent.assign(series.counts.size(), 0.0);
  if (series.regions == 0) return;
  for (std::size_t i = 0; i < series.counts.size(); ++i)
    series.percent[i] = 100.0 * double(series.counts[i]) / double(series.regions);
}

Json seriesJson(const QualityHistogramSeries& series) {
  Json j;
  j["regions"] = series.regions;
  j["undefined"] = series.undefined;
  j["counts"] = series.counts;
  j["percent"] = series.percent;
  return j;
}

}  // namespace

QualityHistogram cumulativeQualityHistogram(const std::vector<GraspRecord>& records, std::size_t fingers) {
  QualityHistogram histogram;
  histogram.fingers = fingers;
  for (int k = kThresholdSteps; k >= 0; --k) {
    // k / 10 rather than repeated subtraction, so that 0.7 is the double 0.7.
    histogram.thresholds.push_back(double(k) / double(kThresholdSteps));
    histogram.labels.push_back(formatFixed(histogram.thresholds.back(), 1));
  }
  histogram.labels.push_back("<0");
  for (auto* series : {&histogram.raw, &histogram.filtered}) series->counts.assign(histogram.labels.size(), 0);

  for (const auto& record : records) {
    if (!record.evaluated || (fingers != 0 && record.fingers != fingers)) continue;
    ++histogram.evaluated_grasps;
    addMesh(histogram.raw, record.raw, histogram.thresholds);
    addMesh(histogram.filtered, record.filtered, histogram.thresholds);
  }
  finishPercent(histogram.raw);
  finishPercent(histogram.filtered);
  return histogram;
}

std::string qualityHistogramJson(const QualityHistogram& histogram) {
  Json j;
  j["fingers"] = histogram.fingers == 0 ? Json(nullptr) : Json(histogram.fingers);
  j["evaluated_grasps"] = histogram.evaluated_grasps;
  j["labels"] = histogram.labels;
  j["thresholds"] = histogram.thresholds;
  j["raw"] = seriesJson(histogram.raw);
  j["filtered"] = seriesJson(histogram.filtered);
  return j.dump(2) + "\n";
}

void writeQualityHistogramJson(const std::string& path, const QualityHistogram& histogram) {
  writeFileAtomically(path, qualityHistogramJson(histogram));
}

}  // namespace icrkit::eval
