#include <icrkit/eval/experiment_outputs.hpp>

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/eval/quality_histogram.hpp>
#include <icrkit/eval/results_tables.hpp>
#include <icrkit/eval/table_one_plot.hpp>

#include <algorithm>
#include <filesystem>

namespace icrkit::eval {

std::vector<std::string> writeExperimentOutputs(const std::string& directory, std::vector<GraspRecord> records,
                                                const ExperimentOutputs& outputs) {
  namespace fs = std::filesystem;
  const fs::path dir(directory);
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw InputError(directory, "", "cannot create the directory: " + error.message());
  std::sort(records.begin(), records.end());

  std::vector<std::string> written;
  const auto path = [&](const std::string& name) {
    written.push_back((dir / name).string());
    return written.back();
  };
  writeGraspRecords(path("grasps.jsonl"), records);
  TableOneOptions table_options;
  table_options.dataset_order = outputs.dataset_order;
  writeResultsTables(directory, records, table_options);
  for (const char* name : {"table1.md", "table1.csv", "table1.json", "eligibility.json"}) path(name);
  const TableOne table = computeTableOne(records, table_options);
  writeTableOneSvg(path("table1.svg"), table);
  writeTableOnePng(path("table1.png"), table);
  for (const std::size_t fingers : outputs.finger_counts) {
    const QualityHistogram histogram = cumulativeQualityHistogram(records, fingers);
    const std::string stem = "fig8_" + std::to_string(fingers) + "fingers";
    writeQualityHistogramSvg(path(stem + ".svg"), histogram);
    writeQualityHistogramPng(path(stem + ".png"), histogram);
    writeQualityHistogramJson(path(stem + ".json"), histogram);
  }
  writeFileAtomically(path("run.json"), [&](std::ostream& out) { out << outputs.run_json << "\n"; }, false);
  return written;
}

}  // namespace icrkit::eval
