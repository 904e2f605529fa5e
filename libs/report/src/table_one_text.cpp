#include <icrkit/report/table_one_text.hpp>

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/number_text.hpp>

#include <filesystem>
#include <sstream>

namespace icrkit::report {
namespace {

using eval::PaperTableOneRow;
using eval::TableOne;
using eval::TableOneRow;
using eval::paperTableOneRow;

const char* const kUnsetMarkdown = "–";  // en dash, as tables print "no value"

std::string markdownValue(const std::optional<double>& value) {
  return value ? formatFixed(*value, 1) : std::string(kUnsetMarkdown);
}

std::string markdownEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '|') out += "\\|";
    else if (c == '\n' || c == '\r') out += ' ';
    else out += c;
  }
  return out;
}

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string csvValue(const std::optional<double>& value) { return value ? formatShortest(*value) : std::string(); }

std::string regionCount(std::size_t filtered, std::size_t raw) {
  // Both meshes have one region per finger of an evaluated grasp, so the two
  // counts normally agree; show both only when they do not.
  return filtered == raw ? std::to_string(filtered) : std::to_string(filtered) + " / " + std::to_string(raw);
}

std::string paperPair(const std::optional<PaperTableOneRow>& paper, bool filtered) {
  if (!paper) return kUnsetMarkdown;
  return filtered ? formatFixed(paper->filtered_intersection_percent, 1) + " / " +
                        formatFixed(paper->filtered_false_positive_percent, 1)
                  : formatFixed(paper->raw_intersection_percent, 1) + " / " +
                        formatFixed(paper->raw_false_positive_percent, 1);
}

void markdownRow(std::ostringstream& out, const TableOneRow& row, bool bold) {
  const auto paper = paperTableOneRow(row.dataset);
  const std::string name = bold ? "**" + markdownEscape(row.dataset) + "**" : markdownEscape(row.dataset);
  out << "| " << name << " | " << row.evaluated_grasps << " | " << markdownValue(row.filtered.intersection_percent)
      << " | " << markdownValue(row.filtered.false_positive_percent) << " | "
      << markdownValue(row.raw.intersection_percent) << " | " << markdownValue(row.raw.false_positive_percent)
      << " | " << paperPair(paper, true) << " | " << paperPair(paper, false) << " | "
      << regionCount(row.filtered.regions, row.raw.regions) << " | "
      << regionCount(row.filtered.degenerate_regions, row.raw.degenerate_regions) << " |\n";
}

void csvRow(std::ostringstream& out, const TableOneRow& row) {
  const auto paper = paperTableOneRow(row.dataset);
  auto paperValue = [&](double PaperTableOneRow::*field) {
    return paper ? formatShortest((*paper).*field) : std::string();
  };
  out << csvField(row.dataset) << ',' << row.evaluated_grasps << ',' << csvValue(row.filtered.intersection_percent)
      << ',' << csvValue(row.filtered.false_positive_percent) << ',' << csvValue(row.raw.intersection_percent) << ','
      << csvValue(row.raw.false_positive_percent) << ',' << row.filtered.regions << ','
      << row.filtered.degenerate_regions << ',' << row.raw.regions << ',' << row.raw.degenerate_regions << ','
      << paperValue(&PaperTableOneRow::filtered_intersection_percent) << ','
      << paperValue(&PaperTableOneRow::filtered_false_positive_percent) << ','
      << paperValue(&PaperTableOneRow::raw_intersection_percent) << ','
      << paperValue(&PaperTableOneRow::raw_false_positive_percent) << '\n';
}

}  // namespace

std::string tableOneMarkdown(const TableOne& table) {
  std::ostringstream out;
  out << "Table I: intersection (Int) and false-positive (FP) areas as a percentage of the ICR area on the "
         "CAD mesh; medians over all regions of the evaluated grasps ("
      << (table.fingers == 0 ? std::string("all finger counts") : std::to_string(table.fingers) + " fingers")
      << "). Average = mean of the per-dataset medians. Degenerate regions (CAD region area 0) are left out of "
         "the medians.\n\n";
  out << "| Dataset | Grasps | Smooth Int [%] | Smooth FP [%] | Raw Int [%] | Raw FP [%] | Paper smooth Int / FP [%] "
         "| Paper raw Int / FP [%] | Regions | Degenerate |\n";
  out << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& row : table.rows) markdownRow(out, row, false);
  markdownRow(out, table.average, true);
  return out.str();
}

std::string tableOneCsv(const TableOne& table) {
  std::ostringstream out;
  out << "dataset,evaluated_grasps,filtered_median_intersection_percent,filtered_median_false_positive_percent,"
         "raw_median_intersection_percent,raw_median_false_positive_percent,filtered_regions,"
         "filtered_degenerate_regions,raw_regions,raw_degenerate_regions,paper_filtered_intersection_percent,"
         "paper_filtered_false_positive_percent,paper_raw_intersection_percent,paper_raw_false_positive_percent\n";
  for (const auto& row : table.rows) csvRow(out, row);
  csvRow(out, table.average);
  return out.str();
}

void writeTableOneMarkdown(const std::string& path, const TableOne& table) {
  writeFileAtomically(path, tableOneMarkdown(table));
}
void writeTableOneCsv(const std::string& path, const TableOne& table) {
  writeFileAtomically(path, tableOneCsv(table));
}
void writeResultsTables(const std::string& directory, const std::vector<eval::GraspRecord>& records,
                        const eval::TableOneOptions& options) {
  const std::filesystem::path dir(directory);
  const TableOne table = eval::computeTableOne(records, options);
  writeTableOneMarkdown((dir / "table1.md").string(), table);
  writeTableOneCsv((dir / "table1.csv").string(), table);
  eval::writeTableOneJson((dir / "table1.json").string(), table);
  eval::writeEligibilityJson((dir / "eligibility.json").string(), eval::computeEligibility(records, options));
}

}  // namespace icrkit::report
