#include <icrkit/report/experiment_outputs.hpp>

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/report/conservative_plot.hpp>
#include <icrkit/report/quality_plot.hpp>
#include <icrkit/report/table_one_plot.hpp>
#include <icrkit/report/table_one_text.hpp>

#include <algorithm>
#include <filesystem>

namespace icrkit::report {

WrittenOutputs writeExperimentOutputs(const std::string& directory, std::vector<eval::GraspRecord> records,
                                                const ExperimentOutputs& outputs) {
  namespace fs = std::filesystem;
  const fs::path dir(directory);
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw InputError(directory, "", "cannot create the directory: " + error.message());
  std::sort(records.begin(), records.end());

  WrittenOutputs written;
  const auto path = [&](const std::string& name) {
    written.files.push_back((dir / name).string());
    return written.files.back();
  };
  eval::writeGraspRecords(path("grasps.jsonl"), records);
  eval::TableOneOptions table_options;
  table_options.dataset_order = outputs.dataset_order;
  written.table = eval::computeTableOne(records, table_options);
  written.eligibility = eval::computeEligibility(records, table_options);
  writeTableOneMarkdown(path("table1.md"), written.table);
  writeTableOneCsv(path("table1.csv"), written.table);
  eval::writeTableOneJson(path("table1.json"), written.table);
  eval::writeEligibilityJson(path("eligibility.json"), written.eligibility);
  writeTableOneSvg(path("table1.svg"), written.table);
  writeTableOnePng(path("table1.png"), written.table);
  for (const std::size_t fingers : outputs.finger_counts) {
    const eval::QualityHistogram histogram = eval::cumulativeQualityHistogram(records, fingers);
    const std::string stem = "fig8_" + std::to_string(fingers) + "fingers";
    writeQualityHistogramSvg(path(stem + ".svg"), histogram);
    writeQualityHistogramPng(path(stem + ".png"), histogram);
    eval::writeQualityHistogramJson(path(stem + ".json"), histogram);
  }
  const eval::ConservativeSummary growth = eval::computeConservativeSummary(records);
  for (std::string& file : writeConservativeSummary(directory, growth)) written.files.push_back(std::move(file));
  writeFileAtomically(path("run.json"), [&](std::ostream& out) { out << outputs.run_json << "\n"; }, false);
  return written;
}

}  // namespace icrkit::report
