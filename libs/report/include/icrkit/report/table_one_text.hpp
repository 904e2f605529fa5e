#pragma once
/// \file
/// Table I as text: Markdown (our medians beside the paper's) and CSV, and
/// the writer of a run's tables (table1.md, table1.csv, table1.json and
/// eligibility.json).

#include <icrkit/eval/results_tables.hpp>

#include <string>
#include <vector>

namespace icrkit::report {

/// Markdown: Int/FP with one decimal, "–" for unset, and the paper's values
/// next to ours for the paper's datasets.
std::string tableOneMarkdown(const eval::TableOne& table);
/// CSV: one header line, one line per row then Average; unset is empty;
/// numbers with full precision.
std::string tableOneCsv(const eval::TableOne& table);

/// Atomic writers of the forms above.
void writeTableOneMarkdown(const std::string& path, const eval::TableOne& table);
void writeTableOneCsv(const std::string& path, const eval::TableOne& table);

/// Computes Table I and eligibility and writes DIR/table1.md, DIR/table1.csv, DIR/table1.json and
/// DIR/eligibility.json (DIR must exist).
void writeResultsTables(const std::string& directory, const std::vector<eval::GraspRecord>& records,
                        const eval::TableOneOptions& options = {});

}  // namespace icrkit::report
