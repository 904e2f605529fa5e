#include <icrkit/eval/experiment_records.hpp>

#include <icrkit/core/error.hpp>

#include <gtest/gtest.h>

#include <test_support.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace icrkit::eval {
namespace {

std::uint64_t bits(double value) {
  std::uint64_t b;
  std::memcpy(&b, &value, sizeof b);
  return b;
}

void expectSameDouble(double expected, double actual, const std::string& what) {
  EXPECT_EQ(bits(expected), bits(actual)) << what << ": expected " << expected << ", got " << actual;
}

void expectSameOptional(const std::optional<double>& expected, const std::optional<double>& actual,
                        const std::string& what) {
  ASSERT_EQ(expected.has_value(), actual.has_value()) << what;
  if (expected) expectSameDouble(*expected, *actual, what);
}

void expectSameMesh(const MeshOutcome& expected, const MeshOutcome& actual, const std::string& what) {
  EXPECT_EQ(expected.contacts, actual.contacts) << what;
  EXPECT_EQ(expected.preselection_passed, actual.preselection_passed) << what;
  EXPECT_EQ(expected.task_fulfilled, actual.task_fulfilled) << what;
  expectSameDouble(expected.epsilon, actual.epsilon, what + ".epsilon");
  EXPECT_EQ(expected.reason, actual.reason) << what;
  ASSERT_EQ(expected.regions.size(), actual.regions.size()) << what;
  for (std::size_t i = 0; i < expected.regions.size(); ++i) {
    const auto& e = expected.regions[i];
    const auto& a = actual.regions[i];
    const std::string at = what + ".regions[" + std::to_string(i) + "]";
    EXPECT_EQ(e.vertices, a.vertices) << at;
    expectSameDouble(e.area_m2, a.area_m2, at + ".area_m2");
    expectSameDouble(e.intersection_area_m2, a.intersection_area_m2, at + ".intersection_area_m2");
    expectSameDouble(e.false_positive_area_m2, a.false_positive_area_m2, at + ".false_positive_area_m2");
    expectSameOptional(e.intersection_percent, a.intersection_percent, at + ".intersection_percent");
    expectSameOptional(e.false_positive_percent, a.false_positive_percent, at + ".false_positive_percent");
    expectSameDouble(e.d1_m, a.d1_m, at + ".d1_m");
    expectSameDouble(e.d2_m, a.d2_m, at + ".d2_m");
    expectSameOptional(e.quality, a.quality, at + ".quality");
  }
  ASSERT_EQ(expected.snapped.has_value(), actual.snapped.has_value()) << what;
  if (expected.snapped) {
    const SnappedOutcome& e = *expected.snapped;
    const SnappedOutcome& a = *actual.snapped;
    EXPECT_EQ(e.contacts, a.contacts) << what;
    ASSERT_EQ(e.move_distances_m.size(), a.move_distances_m.size()) << what;
    for (std::size_t i = 0; i < e.move_distances_m.size(); ++i)
      expectSameDouble(e.move_distances_m[i], a.move_distances_m[i], what + ".snapped.move_distances_m");
    EXPECT_EQ(e.task_fulfilled, a.task_fulfilled) << what;
    expectSameDouble(e.epsilon, a.epsilon, what + ".snapped.epsilon");
    EXPECT_EQ(e.reason, a.reason) << what;
  }
}

void expectSameRecord(const GraspRecord& expected, const GraspRecord& actual) {
  EXPECT_EQ(expected.dataset, actual.dataset);
  EXPECT_EQ(expected.fingers, actual.fingers);
  EXPECT_EQ(expected.index, actual.index);
  EXPECT_EQ(expected.cad_contacts, actual.cad_contacts);
  expectSameDouble(expected.cad_epsilon, actual.cad_epsilon, "cad_epsilon");
  expectSameDouble(expected.tws_radius, actual.tws_radius, "tws_radius");
  ASSERT_EQ(expected.cad_region_areas_m2.size(), actual.cad_region_areas_m2.size());
  for (std::size_t i = 0; i < expected.cad_region_areas_m2.size(); ++i)
    expectSameDouble(expected.cad_region_areas_m2[i], actual.cad_region_areas_m2[i], "cad_region_areas_m2");
  expectSameMesh(expected.raw, actual.raw, "raw");
  expectSameMesh(expected.filtered, actual.filtered, "filtered");
  EXPECT_EQ(expected.evaluated, actual.evaluated);
  ASSERT_EQ(expected.seen_rim_distance_m.has_value(), actual.seen_rim_distance_m.has_value());
  if (expected.seen_rim_distance_m)
    expectSameDouble(*expected.seen_rim_distance_m, *actual.seen_rim_distance_m, "seen_rim_distance_m");
}

RegionComparison region(double area, std::optional<double> percent, std::optional<double> quality) {
  RegionComparison r;
  r.vertices = 17;
  r.area_m2 = area;
  r.intersection_area_m2 = area / 3.0;
  r.false_positive_area_m2 = area / 7.0;
  r.intersection_percent = percent;
  r.false_positive_percent = percent ? std::optional<double>(*percent / 11.0) : std::nullopt;
  r.d1_m = 0.1 + 0.2;
  r.d2_m = -1.0 / 3.0;
  r.quality = quality;
  return r;
}

GraspRecord sampleRecord(const std::string& dataset = "cup_kinect_B", std::size_t fingers = 4, std::size_t index = 7) {
  GraspRecord record;
  record.dataset = dataset;
  record.fingers = fingers;
  record.index = index;
  record.cad_contacts = {0, 12, 345, 2147483647};
  record.cad_epsilon = 0.1 + 0.2;  // 0.30000000000000004
  record.tws_radius = 0.8 * (0.1 + 0.2);
  record.cad_region_areas_m2 = {1e-300, 5e-324, std::numeric_limits<double>::max(), 0.0};
  record.raw.contacts = {1, 2, 3, 4};
  record.raw.task_fulfilled = true;
  record.raw.epsilon = 2.0 / 3.0;
  record.raw.regions = {region(1.0 / 3.0, 12.5, 0.7), region(-0.0, std::nullopt, std::nullopt)};
  record.filtered.contacts = {};
  record.filtered.preselection_passed = false;
  record.filtered.task_fulfilled = false;
  record.filtered.epsilon = -0.0;
  record.filtered.reason = "contact 2 on an excluded vertex \"quoted\"\tand tabbed";
  record.filtered.regions = {region(123456.789e-9, 99.99999999999999, -2.5)};
  record.evaluated = true;
  return record;
}

TEST(Records, RoundTripIsBitExact) {
  const GraspRecord record = sampleRecord();
  const std::string line = toJsonLine(record);
  EXPECT_EQ(line.find('\n'), std::string::npos);
  expectSameRecord(record, fromJsonLine(line));
  // Writing what was read gives the same text again.
  EXPECT_EQ(line, toJsonLine(fromJsonLine(line)));
}

GraspRecord snappedRecord() {
  GraspRecord record = sampleRecord();
  record.filtered.contacts = {1, 2, 3, 4};
  SnappedOutcome snapped;
  snapped.contacts = {1, 9, 3, 4};
  snapped.move_distances_m = {0.0, 1.0 / 3.0 * 1e-3, -0.0, 5e-324};
  snapped.task_fulfilled = true;
  snapped.epsilon = 0.1 + 0.2;
  record.filtered.snapped = snapped;
  return record;
}

TEST(Records, SnappedOutcomeRoundTripsBitExact) {
  GraspRecord record = snappedRecord();
  const std::string line = toJsonLine(record);
  EXPECT_NE(line.find("\"snapped\":{\"contacts\":[1,9,3,4],\"move_distances_m\":["), std::string::npos) << line;
  expectSameRecord(record, fromJsonLine(line));
  EXPECT_EQ(line, toJsonLine(fromJsonLine(line)));
  EXPECT_TRUE(fromJsonLine(line).filtered.eligibleAfterSnapping());
  EXPECT_FALSE(fromJsonLine(line).filtered.eligible());

  // A snapping that failed: no contacts, a reason.
  record.filtered.snapped = SnappedOutcome{};
  record.filtered.snapped->reason = "contact 2: no kept vertex within 1.600 mm of excluded vertex 3";
  const GraspRecord back = fromJsonLine(toJsonLine(record));
  expectSameRecord(record, back);
  EXPECT_FALSE(back.filtered.eligibleAfterSnapping());
}

TEST(Records, RecordsWithoutTheSnappedOutcomeReadAsNotComputed) {
  // Not computed: the key is not written, so such lines are those written
  // before snapping existed, and they read back unset.
  const std::string line = toJsonLine(sampleRecord());
  EXPECT_EQ(line.find("snapped"), std::string::npos);
  const GraspRecord back = fromJsonLine(line);
  EXPECT_FALSE(back.filtered.snapped.has_value());
  EXPECT_FALSE(back.raw.snapped.has_value());
  expectSameRecord(sampleRecord(), back);

  // An explicit null means the same.
  std::string with_null = line;
  const std::size_t regions = with_null.find("\"regions\":", with_null.find("\"filtered\":"));
  with_null.insert(regions, "\"snapped\":null,");
  EXPECT_FALSE(fromJsonLine(with_null).filtered.snapped.has_value());

  // A malformed one names its field.
  std::string malformed = toJsonLine(snappedRecord());
  const std::size_t epsilon = malformed.find("\"epsilon\":", malformed.find("\"snapped\":"));
  malformed.replace(epsilon, 10, "\"epsilon\":\"x\",\"ignored\":");
  try {
    fromJsonLine(malformed, "x", 3);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(e.detail().find("filtered.snapped.epsilon"), std::string::npos) << e.detail();
  }
  std::string not_object = toJsonLine(sampleRecord());
  not_object.insert(not_object.find("\"regions\":", not_object.find("\"filtered\":")), "\"snapped\":[1],");
  EXPECT_THROW(fromJsonLine(not_object, "x", 1), InputError);
}

TEST(Records, SeenRimDistanceRoundTripsAndOlderRecordsLackIt) {
  GraspRecord record = sampleRecord();
  EXPECT_EQ(toJsonLine(record).find("seen_rim_distance_m"), std::string::npos);
  EXPECT_FALSE(fromJsonLine(toJsonLine(record)).seen_rim_distance_m.has_value());
  for (double d : {1.0 / 3.0 * 1e-3, 0.0, std::numeric_limits<double>::infinity()}) {
    record.seen_rim_distance_m = d;
    const std::string line = toJsonLine(record);
    expectSameRecord(record, fromJsonLine(line));
    EXPECT_EQ(line, toJsonLine(fromJsonLine(line)));
  }
  std::string malformed = toJsonLine(record);
  malformed.replace(malformed.find("\"Infinity\""), 10, "true");
  EXPECT_THROW(fromJsonLine(malformed, "x", 1), InputError);
}

TEST(Records, NonFiniteDoublesRoundTrip) {
  GraspRecord record = sampleRecord();
  record.cad_epsilon = std::numeric_limits<double>::infinity();
  record.tws_radius = -std::numeric_limits<double>::infinity();
  record.raw.regions[0].quality = std::numeric_limits<double>::quiet_NaN();
  const GraspRecord back = fromJsonLine(toJsonLine(record));
  EXPECT_EQ(back.cad_epsilon, std::numeric_limits<double>::infinity());
  EXPECT_EQ(back.tws_radius, -std::numeric_limits<double>::infinity());
  ASSERT_TRUE(back.raw.regions[0].quality.has_value());  // NaN is not "unset"
  EXPECT_TRUE(std::isnan(*back.raw.regions[0].quality));
}

TEST(Records, SnakeCaseKeysWithUnitsAndNullForUnset) {
  const std::string line = toJsonLine(sampleRecord());
  for (const char* key : {"\"dataset\":", "\"fingers\":", "\"index\":", "\"cad_contacts\":", "\"cad_epsilon\":",
                          "\"tws_radius\":", "\"cad_region_areas_m2\":", "\"raw\":", "\"filtered\":",
                          "\"evaluated\":", "\"preselection_passed\":", "\"task_fulfilled\":", "\"area_m2\":",
                          "\"intersection_area_m2\":", "\"false_positive_area_m2\":", "\"intersection_percent\":",
                          "\"false_positive_percent\":", "\"d1_m\":", "\"d2_m\":", "\"quality\":"})
    EXPECT_NE(line.find(key), std::string::npos) << key;
  EXPECT_NE(line.find("\"quality\":null"), std::string::npos);
  EXPECT_NE(line.find("\"intersection_percent\":null"), std::string::npos);
  EXPECT_NE(line.find("0.30000000000000004"), std::string::npos);
  EXPECT_EQ(line.rfind("{\"dataset\":\"cup_kinect_B\"", 0), 0u) << "dataset comes first";
}

TEST(Records, OrderIsDatasetFingersIndex) {
  EXPECT_TRUE(sampleRecord("a", 5, 9) < sampleRecord("b", 4, 0));
  EXPECT_TRUE(sampleRecord("a", 4, 9) < sampleRecord("a", 5, 0));
  EXPECT_TRUE(sampleRecord("a", 4, 2) < sampleRecord("a", 4, 10));
  EXPECT_FALSE(sampleRecord("a", 4, 2) < sampleRecord("a", 4, 2));
}

TEST(Records, FileRoundTripSortsAndAllowsBlankLines) {
  test::ScratchDir scratch;
  const std::string path = scratch.file("grasps.jsonl");
  const std::vector<GraspRecord> records = {sampleRecord("b", 4, 1), sampleRecord("a", 5, 0),
                                            sampleRecord("a", 4, 3), sampleRecord("a", 4, 2)};
  writeGraspRecords(path, records);
  std::vector<GraspRecord> back = readGraspRecords(path);
  ASSERT_EQ(back.size(), 4u);
  EXPECT_EQ(back[0].dataset + std::to_string(back[0].fingers) + std::to_string(back[0].index), "a42");
  EXPECT_EQ(back[1].index, 3u);
  EXPECT_EQ(back[2].fingers, 5u);
  EXPECT_EQ(back[3].dataset, "b");
  expectSameRecord(records[0], back[3]);

  // Shards merge by concatenation; blank lines and CRLF endings are fine.
  {
    std::ofstream out(path, std::ios::app | std::ios::binary);
    out << "\n   \r\n" << toJsonLine(sampleRecord("c", 4, 0)) << "\r\n\n";
  }
  back = readGraspRecords(path);
  ASSERT_EQ(back.size(), 5u);
  EXPECT_EQ(back[4].dataset, "c");
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}

TEST(Records, MalformedLineNamesTheLine) {
  test::ScratchDir scratch;
  const std::string path = scratch.file("grasps.jsonl");
  {
    std::ofstream out(path, std::ios::binary);
    out << toJsonLine(sampleRecord()) << "\n\n{\"dataset\": \"cup\", \"fingers\": \n";
  }
  try {
    readGraspRecords(path);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), path);
    EXPECT_EQ(e.location(), "line 3");
    EXPECT_NE(e.detail().find("JSON"), std::string::npos) << e.detail();
  }
}

TEST(Records, MissingOrWrongFieldIsNamed) {
  std::string line = toJsonLine(sampleRecord());
  // Drop the filtered mesh's d2_m: the path of the field is in the message.
  const std::string filteredPart = line.substr(line.find("\"filtered\":"));
  const std::size_t at = line.find("\"filtered\":") + filteredPart.find("\"d2_m\":");
  const std::size_t end = line.find(',', at);
  line.erase(at, end - at + 1);
  try {
    fromJsonLine(line, "shard.jsonl", 12);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "shard.jsonl");
    EXPECT_EQ(e.location(), "line 12");
    EXPECT_NE(e.detail().find("filtered.regions[0].d2_m"), std::string::npos) << e.detail();
  }

  std::string wrongType = toJsonLine(sampleRecord());
  const std::size_t fingers = wrongType.find("\"fingers\":4");
  ASSERT_NE(fingers, std::string::npos);
  wrongType.replace(fingers, 11, "\"fingers\":-4");
  EXPECT_THROW(fromJsonLine(wrongType, "x", 1), InputError);
  EXPECT_THROW(fromJsonLine("[1, 2, 3]", "x", 1), InputError);
  EXPECT_THROW(fromJsonLine("", "x", 1), InputError);
  EXPECT_THROW(fromJsonLine(toJsonLine(sampleRecord()) + " trailing", "x", 1), InputError);
}

TEST(Records, MissingFileIsInputError) {
  test::ScratchDir scratch;
  const std::string path = scratch.file("does_not_exist.jsonl");
  try {
    readGraspRecords(path);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), path);
  }
}

TEST(Records, EmptyFileHasNoRecords) {
  test::ScratchDir scratch;
  const std::string path = scratch.file("empty.jsonl");
  writeGraspRecords(path, {});
  EXPECT_TRUE(std::filesystem::exists(path));
  EXPECT_TRUE(readGraspRecords(path).empty());
}

}  // namespace
}  // namespace icrkit::eval
