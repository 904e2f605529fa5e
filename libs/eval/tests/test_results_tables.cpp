#include <icrkit/eval/results_tables.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/report/table_one_text.hpp>

#include <gtest/gtest.h>

#include <test_support.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

namespace icrkit::eval {
namespace {

/// Percent pairs (Int, FP) of one mesh's regions; a negative Int means "unset" (CAD area 0).
using Percents = std::vector<std::pair<double, double>>;

MeshOutcome meshWith(const Percents& percents) {
  MeshOutcome mesh;
  mesh.task_fulfilled = true;
  for (const auto& [in, fp] : percents) {
    RegionComparison region;
    if (in >= 0) {
      region.intersection_percent = in;
      region.false_positive_percent = fp;
    }
    mesh.regions.push_back(region);
  }
  return mesh;
}

GraspRecord evaluated(const std::string& dataset, std::size_t fingers, std::size_t index, const Percents& filtered,
                      const Percents& raw) {
  GraspRecord record;
  record.dataset = dataset;
  record.fingers = fingers;
  record.index = index;
  record.filtered = meshWith(filtered);
  record.raw = meshWith(raw);
  record.evaluated = true;
  return record;
}

GraspRecord notEvaluated(const std::string& dataset, std::size_t fingers, std::size_t index, bool rawEligible,
                         bool filteredPreselection, bool filteredTask) {
  GraspRecord record;
  record.dataset = dataset;
  record.fingers = fingers;
  record.index = index;
  record.raw.task_fulfilled = rawEligible;
  record.filtered.preselection_passed = filteredPreselection;
  record.filtered.task_fulfilled = filteredTask;
  record.evaluated = false;
  return record;
}

TEST(TableOne, MedianOddEvenEmpty) {
  EXPECT_EQ(median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(median({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_EQ(median({7.0}), 7.0);
  EXPECT_FALSE(median({}).has_value());
  EXPECT_EQ(median({std::numeric_limits<double>::quiet_NaN(), 5.0, 1.0, 3.0}), 3.0);
}

TEST(TableOne, KnownMediansFromHandMadeRecords) {
  std::vector<GraspRecord> records;
  // Dataset "a": 4- and 5-finger grasps pooled, one degenerate region left out.
  records.push_back(evaluated("a", 4, 0, {{10, 1}, {20, 2}, {30, 3}, {40, 4}}, {{1, 0}, {2, 0}, {3, 0}, {4, 0}}));
  records.push_back(evaluated("a", 5, 0, {{50, 5}, {60, 6}, {70, 7}, {80, 8}, {-1, 0}},
                              {{5, 0}, {6, 0}, {7, 0}, {8, 0.5}, {-1, 0}}));
  // Not evaluated: its (stray) regions must not count.
  GraspRecord stray = evaluated("a", 4, 1, {{1000, 1000}}, {{1000, 1000}});
  stray.evaluated = false;
  records.push_back(stray);
  // Dataset "b": odd count.
  records.push_back(evaluated("b", 4, 0, {{90, 30}, {10, 10}, {50, 20}}, {{0, 0}, {20, 0}, {10, 0}}));

  const TableOne table = computeTableOne(records);
  ASSERT_EQ(table.rows.size(), 2u);
  const TableOneRow& a = table.rows[0];
  EXPECT_EQ(a.dataset, "a");
  EXPECT_EQ(a.evaluated_grasps, 2u);
  EXPECT_EQ(a.filtered.regions, 9u);
  EXPECT_EQ(a.filtered.degenerate_regions, 1u);
  EXPECT_EQ(a.raw.regions, 9u);
  EXPECT_EQ(a.raw.degenerate_regions, 1u);
  EXPECT_EQ(a.filtered.intersection_percent, 45.0);  // median of 10..80
  EXPECT_EQ(a.filtered.false_positive_percent, 4.5);
  EXPECT_EQ(a.raw.intersection_percent, 4.5);
  EXPECT_EQ(a.raw.false_positive_percent, 0.0);

  const TableOneRow& b = table.rows[1];
  EXPECT_EQ(b.filtered.intersection_percent, 50.0);
  EXPECT_EQ(b.filtered.false_positive_percent, 20.0);
  EXPECT_EQ(b.raw.intersection_percent, 10.0);

  // Average = mean of the medians, counts are totals.
  EXPECT_EQ(table.average.dataset, "Average");
  EXPECT_EQ(table.average.evaluated_grasps, 3u);
  EXPECT_DOUBLE_EQ(*table.average.filtered.intersection_percent, 47.5);
  EXPECT_DOUBLE_EQ(*table.average.filtered.false_positive_percent, 12.25);
  EXPECT_DOUBLE_EQ(*table.average.raw.intersection_percent, 7.25);
  EXPECT_EQ(table.average.filtered.regions, 12u);

  TableOneOptions fourOnly;
  fourOnly.fingers = 4;
  const TableOne four = computeTableOne(records, fourOnly);
  EXPECT_EQ(four.rows[0].evaluated_grasps, 1u);
  EXPECT_EQ(four.rows[0].filtered.intersection_percent, 25.0);
}

TEST(TableOne, DatasetOrderAndEmptyRows) {
  std::vector<GraspRecord> records = {evaluated("zeta", 4, 0, {{10, 1}}, {{1, 0}}),
                                      evaluated("alpha", 4, 0, {{30, 3}}, {{3, 0}}),
                                      evaluated("mid", 4, 0, {{20, 2}}, {{2, 0}})};
  const TableOne sorted = computeTableOne(records);
  ASSERT_EQ(sorted.rows.size(), 3u);
  EXPECT_EQ(sorted.rows[0].dataset, "alpha");
  EXPECT_EQ(sorted.rows[1].dataset, "mid");
  EXPECT_EQ(sorted.rows[2].dataset, "zeta");

  TableOneOptions options;
  options.dataset_order = {"zeta", "missing", "zeta"};
  const TableOne listed = computeTableOne(records, options);
  ASSERT_EQ(listed.rows.size(), 4u);
  EXPECT_EQ(listed.rows[0].dataset, "zeta");
  EXPECT_EQ(listed.rows[1].dataset, "missing");
  EXPECT_FALSE(listed.rows[1].filtered.intersection_percent.has_value());
  EXPECT_EQ(listed.rows[1].evaluated_grasps, 0u);
  EXPECT_EQ(listed.rows[2].dataset, "alpha");
  EXPECT_EQ(listed.rows[3].dataset, "mid");
  // The empty row does not pull the average down.
  EXPECT_DOUBLE_EQ(*listed.average.filtered.intersection_percent, 20.0);

  const TableOne none = computeTableOne({});
  EXPECT_TRUE(none.rows.empty());
  EXPECT_FALSE(none.average.filtered.intersection_percent.has_value());
  EXPECT_FALSE(none.average.raw.false_positive_percent.has_value());
}

TEST(TableOne, PaperRowsAsRecordsReproduceThePaperAverage) {
  const PaperTableOne paper = paperTableOne();
  ASSERT_EQ(paper.rows.size(), 9u);
  std::vector<GraspRecord> records;
  TableOneOptions options;
  for (const auto& row : paper.rows) {
    options.dataset_order.push_back(row.dataset);
    // Three regions whose median is the paper's value.
    records.push_back(evaluated(row.dataset, 4, 0,
                                {{row.filtered_intersection_percent - 5, row.filtered_false_positive_percent},
                                 {row.filtered_intersection_percent, row.filtered_false_positive_percent + 3}},
                                {{row.raw_intersection_percent, row.raw_false_positive_percent},
                                 {row.raw_intersection_percent, row.raw_false_positive_percent}}));
    records.push_back(evaluated(row.dataset, 5, 0,
                                {{row.filtered_intersection_percent + 1, row.filtered_false_positive_percent - 1}},
                                {{row.raw_intersection_percent + 7, row.raw_false_positive_percent}}));
  }
  const TableOne table = computeTableOne(records, options);
  ASSERT_EQ(table.rows.size(), 9u);
  for (std::size_t i = 0; i < 9; ++i) {
    EXPECT_EQ(table.rows[i].dataset, paper.rows[i].dataset);
    EXPECT_DOUBLE_EQ(*table.rows[i].filtered.intersection_percent, paper.rows[i].filtered_intersection_percent);
    EXPECT_DOUBLE_EQ(*table.rows[i].filtered.false_positive_percent, paper.rows[i].filtered_false_positive_percent);
    EXPECT_DOUBLE_EQ(*table.rows[i].raw.intersection_percent, paper.rows[i].raw_intersection_percent);
    EXPECT_DOUBLE_EQ(*table.rows[i].raw.false_positive_percent, paper.rows[i].raw_false_positive_percent);
  }
  // 59 = mean of 56, 54, 49, 62, 70, 50, 59, 58, 73; the raw Int mean is 12.4, printed as 12.
  EXPECT_DOUBLE_EQ(*table.average.filtered.intersection_percent, 59.0);
  EXPECT_DOUBLE_EQ(*table.average.filtered.false_positive_percent, 9.0);
  EXPECT_NEAR(*table.average.raw.intersection_percent, 12.0, 0.5);
  EXPECT_DOUBLE_EQ(*table.average.raw.false_positive_percent, 0.0);
  EXPECT_EQ(std::lround(*table.average.raw.intersection_percent), std::lround(paper.average.raw_intersection_percent));
  EXPECT_DOUBLE_EQ(paper.average.filtered_intersection_percent, 59.0);
  EXPECT_DOUBLE_EQ(paper.average.filtered_false_positive_percent, 9.0);
  EXPECT_DOUBLE_EQ(paper.filtered_eligible_percent, 98.3);
  EXPECT_DOUBLE_EQ(paper.raw_eligible_percent, 88.0);
}

TEST(TableOne, PaperRowLookup) {
  const auto cup = paperTableOneRow("cup_sr4000_A");
  ASSERT_TRUE(cup.has_value());
  EXPECT_EQ(cup->sensor, "SR4000");
  EXPECT_EQ(cup->filtered_intersection_percent, 56.0);
  EXPECT_EQ(cup->filtered_false_positive_percent, 2.0);
  const auto toy = paperTableOneRow("wooden_toy_1_kinect_B");
  ASSERT_TRUE(toy.has_value());
  EXPECT_EQ(toy->filtered_false_positive_percent, 21.0);  // the 21 % of Section V
  EXPECT_EQ(paperTableOneRow("coffee_pot_kinect_B")->raw_intersection_percent, 2.0);
  EXPECT_TRUE(paperTableOneRow("Average").has_value());
  EXPECT_FALSE(paperTableOneRow("cup_kinect_A").has_value());
}

TEST(TableEligibility, CountsAndRates) {
  std::vector<GraspRecord> records;
  records.push_back(evaluated("a", 4, 0, {{10, 1}}, {{1, 0}}));
  records.push_back(evaluated("a", 4, 1, {{10, 1}}, {{1, 0}}));
  records.push_back(notEvaluated("a", 4, 2, false, true, true));   // raw lost the task
  records.push_back(notEvaluated("a", 5, 0, true, false, true));   // preselection failed
  records.push_back(notEvaluated("b", 5, 0, false, true, false));  // both lost the task
  const EligibilitySummary summary = computeEligibility(records);
  ASSERT_EQ(summary.datasets.size(), 2u);
  const EligibilityGroup& a = summary.datasets[0];
  EXPECT_EQ(a.dataset, "a");
  EXPECT_EQ(a.all.grasps, 4u);
  EXPECT_EQ(a.all.raw_eligible, 3u);
  EXPECT_EQ(a.all.filtered_eligible, 3u);
  EXPECT_EQ(a.all.filtered_preselection_failed, 1u);
  EXPECT_EQ(a.all.both_eligible, 2u);
  EXPECT_EQ(a.all.evaluated, 2u);
  EXPECT_DOUBLE_EQ(*a.all.percent(a.all.raw_eligible), 75.0);
  ASSERT_EQ(a.by_fingers.size(), 2u);
  EXPECT_EQ(a.by_fingers.at(4).grasps, 3u);
  EXPECT_EQ(a.by_fingers.at(4).raw_eligible, 2u);
  EXPECT_EQ(a.by_fingers.at(5).filtered_preselection_failed, 1u);

  EXPECT_EQ(summary.overall.dataset, "all");
  EXPECT_EQ(summary.overall.all.grasps, 5u);
  EXPECT_EQ(summary.overall.all.filtered_eligible, 3u);
  EXPECT_DOUBLE_EQ(*summary.overall.all.percent(summary.overall.all.filtered_eligible), 60.0);
  EXPECT_EQ(summary.overall.by_fingers.at(5).grasps, 2u);
  EXPECT_FALSE(EligibilityCounts{}.percent(0).has_value());
}

GraspRecord snappedTo(GraspRecord record, bool task) {
  SnappedOutcome snapped;
  snapped.contacts = {1, 2, 3, 4};
  snapped.move_distances_m = {0.001, 0.0, 0.0, 0.0};
  snapped.task_fulfilled = task;
  record.filtered.snapped = snapped;
  return record;
}

TEST(TableEligibility, AfterSnappingIsCountedBesideTheStrictCheck) {
  std::vector<GraspRecord> records;
  records.push_back(evaluated("a", 4, 0, {{10, 1}}, {{1, 0}}));                           // strictly eligible
  records.push_back(snappedTo(notEvaluated("a", 4, 1, true, false, true), true));         // eligible once snapped
  records.push_back(snappedTo(notEvaluated("a", 4, 2, true, false, true), false));        // snapped, task lost
  records.push_back(notEvaluated("a", 5, 0, true, false, true));                          // not recorded (older run)
  records.push_back(snappedTo(notEvaluated("b", 5, 0, true, false, false), true));        // eligible once snapped
  const EligibilitySummary summary = computeEligibility(records);
  const EligibilityCounts& a = summary.datasets[0].all;
  EXPECT_EQ(a.filtered_eligible, 1u);
  EXPECT_EQ(a.filtered_eligible_after_snapping, 2u);
  EXPECT_EQ(a.filtered_snapping_not_recorded, 1u);
  EXPECT_EQ(summary.datasets[0].by_fingers.at(4).filtered_eligible_after_snapping, 2u);
  EXPECT_EQ(summary.datasets[0].by_fingers.at(5).filtered_eligible_after_snapping, 0u);
  EXPECT_EQ(summary.datasets[1].all.filtered_eligible_after_snapping, 1u);
  EXPECT_EQ(summary.overall.all.filtered_eligible_after_snapping, 3u);

  // The strict counts, Table I and every existing key are those of the same
  // records without the snapped grasps.
  std::vector<GraspRecord> strict = records;
  for (GraspRecord& r : strict) r.filtered.snapped.reset();
  const EligibilitySummary plain = computeEligibility(strict);
  EXPECT_EQ(plain.overall.all.filtered_eligible, summary.overall.all.filtered_eligible);
  EXPECT_EQ(plain.overall.all.filtered_preselection_failed, summary.overall.all.filtered_preselection_failed);
  EXPECT_EQ(plain.overall.all.both_eligible, summary.overall.all.both_eligible);
  EXPECT_EQ(plain.overall.all.filtered_eligible_after_snapping, 1u);  // only the strictly eligible one
  EXPECT_EQ(tableOneJson(computeTableOne(strict)), tableOneJson(computeTableOne(records)));
  const auto with = nlohmann::json::parse(eligibilityJson(summary));
  const auto without = nlohmann::json::parse(eligibilityJson(plain));
  for (const auto* group : {&without["overall"]["all"], &without["datasets"][0]["all"]}) {
    const auto& counterpart = group == &without["overall"]["all"] ? with["overall"]["all"] : with["datasets"][0]["all"];
    for (const auto& item : group->items()) {
      if (item.key().find("snapping") != std::string::npos) continue;
      EXPECT_EQ(counterpart[item.key()], item.value()) << item.key();
    }
  }
  EXPECT_EQ(with["paper"], without["paper"]);

  // The new keys, per dataset, per finger count and overall, and their label.
  EXPECT_EQ(with["overall"]["all"]["filtered_eligible_after_snapping"].get<int>(), 3);
  EXPECT_DOUBLE_EQ(with["overall"]["all"]["filtered_eligible_after_snapping_percent"].get<double>(), 60.0);
  EXPECT_EQ(with["overall"]["all"]["filtered_snapping_not_recorded"].get<int>(), 1);
  EXPECT_EQ(with["datasets"][0]["all"]["filtered_eligible_after_snapping"].get<int>(), 2);
  EXPECT_EQ(with["datasets"][0]["by_fingers"][0]["filtered_eligible_after_snapping"].get<int>(), 2);
  EXPECT_EQ(with["notes"]["filtered_eligible_after_snapping"].get<std::string>().rfind(
                "after snapping to the nearest kept vertex (not the paper's check)", 0),
            0u);
  EXPECT_TRUE(with["notes"].contains("filtered_snapping_not_recorded"));
}

GraspRecord atRimDistance(GraspRecord record, std::optional<double> distance) {
  record.seen_rim_distance_m = distance;
  return record;
}

TEST(TableEligibility, AwayFromTheSeenRimIsCountedBesideTheStrictCheck) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<GraspRecord> records;
  records.push_back(atRimDistance(evaluated("a", 4, 0, {{10, 1}}, {{1, 0}}), 0.010));          // both eligible, off the rim
  records.push_back(atRimDistance(notEvaluated("a", 4, 1, true, false, true), 0.001));        // on the rim: out
  records.push_back(atRimDistance(notEvaluated("a", 4, 2, true, true, false), inf));          // closed mesh: off the rim
  records.push_back(atRimDistance(notEvaluated("a", 5, 0, false, true, true), 0.003));        // exactly at the bound: out
  records.push_back(atRimDistance(notEvaluated("b", 5, 0, true, false, true), std::nullopt));  // older record
  const EligibilitySummary summary = computeEligibility(records);
  const EligibilityCounts& a = summary.datasets[0].all;
  EXPECT_EQ(a.off_rim_grasps, 2u);
  EXPECT_EQ(a.raw_eligible_off_rim, 2u);
  EXPECT_EQ(a.filtered_eligible_off_rim, 1u);
  EXPECT_EQ(a.rim_not_recorded, 0u);
  EXPECT_DOUBLE_EQ(*a.offRimPercent(a.filtered_eligible_off_rim), 50.0);
  EXPECT_EQ(summary.datasets[0].by_fingers.at(5).off_rim_grasps, 0u);
  EXPECT_FALSE(summary.datasets[0].by_fingers.at(5).offRimPercent(0).has_value());
  EXPECT_EQ(summary.datasets[1].all.rim_not_recorded, 1u);
  EXPECT_EQ(summary.overall.all.off_rim_grasps, 2u);
  // The strict counts are those of the same records without the distances.
  std::vector<GraspRecord> plain = records;
  for (GraspRecord& r : plain) r.seen_rim_distance_m.reset();
  const EligibilitySummary without = computeEligibility(plain);
  EXPECT_EQ(without.overall.all.raw_eligible, summary.overall.all.raw_eligible);
  EXPECT_EQ(without.overall.all.filtered_eligible, summary.overall.all.filtered_eligible);
  EXPECT_EQ(without.overall.all.rim_not_recorded, 5u);
  EXPECT_EQ(tableOneJson(computeTableOne(plain)), tableOneJson(computeTableOne(records)));
  // A wider rim leaves fewer grasps; the bound and the keys are in the JSON.
  TableOneOptions wide;
  wide.seen_rim_distance_m = 0.02;
  EXPECT_EQ(computeEligibility(records, wide).overall.all.off_rim_grasps, 1u);
  const auto json = nlohmann::json::parse(eligibilityJson(summary));
  EXPECT_DOUBLE_EQ(json["seen_rim_distance_m"].get<double>(), 0.003);
  EXPECT_EQ(json["overall"]["all"]["off_rim_grasps"].get<int>(), 2);
  EXPECT_DOUBLE_EQ(json["overall"]["all"]["raw_eligible_off_rim_percent"].get<double>(), 100.0);
  EXPECT_DOUBLE_EQ(json["overall"]["all"]["filtered_eligible_off_rim_percent"].get<double>(), 50.0);
  EXPECT_TRUE(json["notes"].contains("off_rim"));
  TableOneOptions negative;
  negative.seen_rim_distance_m = -1.0;
  EXPECT_THROW(computeEligibility(records, negative), InputError);
}

TEST(TableWriters, WritesAllFourFiles) {
  test::ScratchDir scratch;
  std::vector<GraspRecord> records;
  records.push_back(evaluated("cup_sr4000_A", 4, 0, {{55, 2}, {57, 2}}, {{14, 0}, {14, 0}}));
  records.push_back(notEvaluated("cup_sr4000_A", 5, 0, false, true, true));
  records.push_back(notEvaluated("my, \"odd\" | set", 4, 0, false, false, false));
  report::writeResultsTables(scratch.path().string(), records);

  const std::string md = test::readWholeFile(scratch.file("table1.md"));
  EXPECT_NE(md.find("| cup_sr4000_A | 1 | 56.0 | 2.0 | 14.0 | 0.0 | 56.0 / 2.0 | 14.0 / 0.0 | 2 | 0 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| **Average** |"), std::string::npos) << md;
  EXPECT_NE(md.find("59.0 / 9.0"), std::string::npos) << md;  // the paper's Average next to ours
  EXPECT_NE(md.find("my, \"odd\" \\| set | 0 | – | – | – | – | – | – |"), std::string::npos) << md;

  const std::string csv = test::readWholeFile(scratch.file("table1.csv"));
  std::istringstream lines(csv);
  std::vector<std::string> rows;
  for (std::string line; std::getline(lines, line);) rows.push_back(line);
  ASSERT_EQ(rows.size(), 4u) << csv;
  EXPECT_EQ(rows[0].rfind("dataset,evaluated_grasps,", 0), 0u);
  EXPECT_EQ(rows[1], "cup_sr4000_A,1,56,2,14,0,2,0,2,0,56,2,14,0");
  EXPECT_EQ(rows[2], "\"my, \"\"odd\"\" | set\",0,,,,,0,0,0,0,,,,");
  EXPECT_EQ(rows[3].rfind("Average,1,56,2,14,0,2,0,2,0,59,9,12,0", 0), 0u) << rows[3];

  const auto table = nlohmann::json::parse(test::readWholeFile(scratch.file("table1.json")));
  ASSERT_EQ(table["rows"].size(), 2u);
  EXPECT_TRUE(table["fingers"].is_null());
  EXPECT_EQ(table["rows"][0]["dataset"], "cup_sr4000_A");
  EXPECT_EQ(table["rows"][0]["filtered"]["median_intersection_percent"].get<double>(), 56.0);
  EXPECT_EQ(table["rows"][0]["paper"]["filtered"]["median_intersection_percent"].get<double>(), 56.0);
  EXPECT_TRUE(table["rows"][1]["filtered"]["median_intersection_percent"].is_null());
  EXPECT_TRUE(table["rows"][1]["paper"].is_null());
  EXPECT_EQ(table["average"]["dataset"], "Average");

  const auto eligibility = nlohmann::json::parse(test::readWholeFile(scratch.file("eligibility.json")));
  EXPECT_EQ(eligibility["overall"]["all"]["grasps"].get<int>(), 3);
  EXPECT_NEAR(eligibility["overall"]["all"]["filtered_eligible_percent"].get<double>(), 200.0 / 3.0, 1e-12);
  EXPECT_NEAR(eligibility["overall"]["all"]["raw_eligible_percent"].get<double>(), 100.0 / 3.0, 1e-12);
  EXPECT_EQ(eligibility["overall"]["by_fingers"][0]["fingers"].get<int>(), 4);
  EXPECT_EQ(eligibility["paper"]["filtered_eligible_percent"].get<double>(), 98.3);
  EXPECT_EQ(eligibility["paper"]["raw_eligible_percent"].get<double>(), 88.0);
  ASSERT_EQ(eligibility["datasets"].size(), 2u);

  // Nothing but the four outputs is left behind (no temporaries).
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(scratch.path().string())) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, 4u);

  // Deterministic: writing again gives the same bytes.
  const std::string before = md + csv;
  report::writeResultsTables(scratch.path().string(), records);
  EXPECT_EQ(test::readWholeFile(scratch.file("table1.md")) + test::readWholeFile(scratch.file("table1.csv")), before);
}

}  // namespace
}  // namespace icrkit::eval
