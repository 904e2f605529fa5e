// The study over several datasets (study.hpp) and the merge of its shards'
// run folders (run_merge.hpp): shards together give the unsharded run's
// records bit for bit, a shard asks only for the datasets it touches, mesh
// errors name the file, and merging checks what it joins.

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/eval/run_folder.hpp>
#include <icrkit/eval/run_merge.hpp>
#include <icrkit/eval/study.hpp>

#include "experiment_test_support.hpp"

#include <test_support.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <set>

namespace icrkit::eval {
namespace {

ExperimentConfig smallConfig() {
  ExperimentConfig config;
  config.finger_counts = {3};
  config.grasps_per_set = 3;
  return config;
}

// Two datasets: the ellipsoid against noisy copies of itself.
StudyStages ellipsoidStages(std::vector<std::string>* asked) {
  StudyStages stages;
  stages.meshes = [asked](const std::string& name, std::size_t position, const ProgressCallback&) {
    if (asked) asked->push_back(name);
    StudyMeshes m;
    m.cad = test::ellipsoid(3);
    m.raw = test::noisyCopy(m.cad, 2e-4, 10 + static_cast<unsigned>(position));
    m.filtered = test::noisyCopy(m.cad, 1e-4, 20 + static_cast<unsigned>(position));
    m.files = {name + "/object.ply", name + "/raw.ply", name + "/filtered.ply"};
    return m;
  };
  return stages;
}

TEST(Study, ShardsTogetherGiveTheUnshardedRecords) {
  const std::vector<std::string> names{"first", "second"};
  const ExperimentConfig config = smallConfig();
  std::vector<std::string> asked;
  const StudyResult whole = runStudy(names, config, Shard{}, ellipsoidStages(&asked));
  EXPECT_EQ(asked, names);
  ASSERT_EQ(whole.datasets.size(), 2u);
  EXPECT_EQ(whole.records.size(), 2 * config.nominalItems());
  EXPECT_EQ(whole.datasets[1].first_record, config.nominalItems());
  EXPECT_EQ(whole.datasets[0].grasps_sampled.front().first, 3u);
  EXPECT_GT(whole.datasets[0].lambda_m, 0.0);

  std::vector<GraspRecord> joined;
  for (std::size_t i = 0; i < 3; ++i) {
    asked.clear();
    const StudyResult part = runStudy(names, config, Shard{i, 3}, ellipsoidStages(&asked));
    // Six items in three shards of two: the middle shard spans both datasets.
    EXPECT_EQ(asked.size(), i == 1 ? 2u : 1u) << "shard " << i;
    joined.insert(joined.end(), part.records.begin(), part.records.end());
  }
  EXPECT_EQ(test::recordLines(joined), test::recordLines(whole.records));
}

TEST(Study, StagesAreCalledAndMeshErrorsNameTheFile) {
  std::vector<std::string> notes;
  std::size_t after_records = 0;
  StudyStages stages = ellipsoidStages(nullptr);
  stages.note = [&](const std::string& message) { notes.push_back(message); };
  stages.after = [&](const DatasetMeshes& meshes, const std::vector<GraspRecord>& records) {
    EXPECT_EQ(meshes.name, "only");
    after_records += records.size();
  };
  const StudyResult result = runStudy({"only"}, smallConfig(), Shard{}, stages);
  EXPECT_EQ(after_records, result.records.size());
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0], "[1/1] only: evaluating grasps 0..3");

  StudyStages broken = ellipsoidStages(nullptr);
  broken.meshes = [](const std::string&, std::size_t, const ProgressCallback&) {
    StudyMeshes m;
    m.cad = test::ellipsoid(2);
    m.raw = m.cad;
    m.filtered = m.cad;
    m.filtered.faces.clear();
    m.files.filtered = "rec/filtered.ply";
    return m;
  };
  const InputError error = icrkit::test::expectInputError([&] { runStudy({"x"}, smallConfig(), Shard{}, broken); });
  EXPECT_EQ(error.source(), "rec/filtered.ply");
  EXPECT_EQ(icrkit::test::expectInputError([&] {
              runStudy({"x"}, smallConfig(), Shard{2, 2}, broken);
            }).source(),
            "Shard");
}

// A run folder as `icrkit evaluate --shard i/N` leaves it: run.json and grasps.jsonl.
void writeShard(const std::string& dir, const std::vector<GraspRecord>& records, std::size_t index, std::size_t count,
                std::uint64_t seed = 1) {
  std::filesystem::create_directories(dir);
  writeGraspRecords(RunFolder{dir}.records(), records);
  const nlohmann::json run{{"command", "evaluate"},
                           {"config", {{"finger_counts", {3}}, {"seed", seed}}},
                           {"shard", {{"index", index}, {"count", count}}},
                           {"renders", 1},
                           {"datasets", {{{"name", "first"}}, {{"name", "second"}}}}};
  writeFileAtomically(RunFolder{dir}.runJson(), run.dump());
}

TEST(RunMerge, JoinsShardsAndChecksThem) {
  icrkit::test::ScratchDir scratch;
  const ExperimentConfig config = smallConfig();
  const std::vector<std::string> names{"first", "second"};
  const StudyResult whole = runStudy(names, config, Shard{}, ellipsoidStages(nullptr));
  std::vector<std::string> folders;
  for (std::size_t i = 0; i < 2; ++i) {
    folders.push_back(scratch.file("shard" + std::to_string(i)));
    writeShard(folders.back(), runStudy(names, config, Shard{i, 2}, ellipsoidStages(nullptr)).records, i, 2);
  }
  // A render of the first evaluated grasp of "first", and one no unsharded run keeps.
  const GraspRecord* first_evaluated = nullptr;
  for (const GraspRecord& r : whole.records)
    if (r.evaluated && r.dataset == "first") {
      first_evaluated = &r;
      break;
    }
  ASSERT_NE(first_evaluated, nullptr);
  std::filesystem::create_directories(RunFolder{folders[0]}.renders());
  writeFileAtomically(RunFolder{folders[0]}.render(*first_evaluated, "raw"), std::string("png"));
  writeFileAtomically(
      (std::filesystem::path(RunFolder{folders[0]}.renders()) / "other_9fingers_grasp9_raw.png").string(),
      std::string("png"));

  const MergedRun merged = mergeRunFolders(folders);
  EXPECT_EQ(test::recordLines(merged.records), test::recordLines(whole.records));
  EXPECT_EQ(merged.dataset_order, names);
  EXPECT_EQ(merged.finger_counts, std::vector<std::size_t>{3});
  const nlohmann::json run = nlohmann::json::parse(merged.run_json);
  EXPECT_EQ(run["shard"]["count"], 1);
  EXPECT_EQ(run["merged_from"].size(), 2u);
  ASSERT_EQ(merged.render_files.size(), 1u);
  EXPECT_EQ(std::filesystem::path(merged.render_files[0]).filename().string(),
            renderStem(*first_evaluated) + "raw.png");
  EXPECT_FALSE(merged.sensitivity);

  EXPECT_NE(std::string(icrkit::test::expectInputError([&] { mergeRunFolders({folders[0]}); }).what())
                .find("shards missing: 1 of 2"),
            std::string::npos);
  EXPECT_NE(std::string(icrkit::test::expectInputError([&] {
                          mergeRunFolders({folders[0], folders[0]});
                        }).what())
                .find("given twice"),
            std::string::npos);
  const std::string other = scratch.file("other_seed");
  writeShard(other, {}, 1, 2, 7);
  EXPECT_EQ(icrkit::test::expectInputError([&] {
              mergeRunFolders({folders[0], other});
            }).source(),
            RunFolder{other}.runJson());
  EXPECT_EQ(icrkit::test::expectInputError([&] { mergeRunFolders({scratch.file("none")}); }).source(),
            RunFolder{scratch.file("none")}.runJson());
  EXPECT_EQ(icrkit::test::expectInputError([&] { mergeRunFolders({}); }).source(), "run folders");
}

}  // namespace
}  // namespace icrkit::eval
