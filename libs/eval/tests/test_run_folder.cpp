#include <icrkit/core/error.hpp>
#include <icrkit/eval/run_folder.hpp>

#include <gtest/gtest.h>

#include <test_support.hpp>

#include <filesystem>
#include <fstream>

namespace icrkit::eval {
namespace {

TEST(RunFolder, PathsFollowTheLayout) {
  const RunFolder folder{"out"};
  EXPECT_EQ(folder.records(), (std::filesystem::path("out") / "grasps.jsonl").string());
  EXPECT_EQ(folder.runJson(), (std::filesystem::path("out") / "run.json").string());
  EXPECT_EQ(folder.cadMesh("cup_kinect_B"), (std::filesystem::path("out") / "datasets" / "cup_kinect_B" / "object.ply").string());
  EXPECT_EQ(folder.filteredMesh("cup_kinect_B"),
            (std::filesystem::path("out") / "reconstructions" / "cup_kinect_B" / "filtered.ply").string());
}

TEST(RunFolder, ExperimentConfigRoundTrips) {
  ExperimentConfig config;
  config.finger_counts = {3, 5};
  config.grasps_per_set = 17;
  config.seed = 99;
  config.alpha = 0.4;
  config.friction = 0.6;
  config.cone_edges = 6;
  config.growth = icr::GrowthMode::Full;
  config.metric = DistanceMetric::Euclidean;
  config.mapping.max_line_distance = 0.02;
  config.mapping.neighbourhood_radius = 0.003;
  config.preselection = false;
  config.conservative_sigmas = {0.5, 1.0};
  config.patch = icr::PatchParameters{};
  config.patch->radius_m = 0.002;
  const ExperimentConfig back = experimentConfigFromJson(experimentConfigJson(config));
  EXPECT_EQ(back.finger_counts, config.finger_counts);
  EXPECT_EQ(back.grasps_per_set, config.grasps_per_set);
  EXPECT_EQ(back.seed, config.seed);
  EXPECT_EQ(back.alpha, config.alpha);
  EXPECT_EQ(back.friction, config.friction);
  EXPECT_EQ(back.cone_edges, config.cone_edges);
  EXPECT_EQ(back.growth, config.growth);
  EXPECT_EQ(back.metric, config.metric);
  EXPECT_EQ(back.mapping.max_line_distance, config.mapping.max_line_distance);
  EXPECT_EQ(back.mapping.neighbourhood_radius, config.mapping.neighbourhood_radius);
  EXPECT_EQ(back.preselection, config.preselection);
  EXPECT_EQ(back.conservative_sigmas, config.conservative_sigmas);
  ASSERT_TRUE(back.patch.has_value());
  EXPECT_EQ(back.patch->radius_m, 0.002);
  EXPECT_EQ(experimentConfigJson(back), experimentConfigJson(config));
  // Without the patch study the key is absent, so other runs keep their form.
  EXPECT_EQ(experimentConfigJson(ExperimentConfig{}).find("patch"), std::string::npos);
}

TEST(RunFolder, AbsentConfigGivesThePapersDefaults) {
  const ExperimentConfig defaults;
  for (const char* text : {"null", "{}", "[1, 2]"}) {
    const ExperimentConfig config = experimentConfigFromJson(text);
    EXPECT_EQ(config.finger_counts, defaults.finger_counts) << text;
    EXPECT_EQ(config.alpha, defaults.alpha) << text;
    EXPECT_FALSE(config.patch.has_value()) << text;
  }
  try {
    experimentConfigFromJson(R"({"patch": 3})");
    FAIL() << "a malformed patch was accepted";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "run.json");
    EXPECT_EQ(error.location(), "config.patch");
  }
}

TEST(RunFolder, MeshFilesOfEvaluateAndPaperRuns) {
  const RunFolder folder{"run"};
  const std::string evaluate_run =
      R"({"datasets": [{"name": "bunny", "cad": "/abs/cad.ply", "raw": "/abs/raw.ply", "filtered": "/abs/f.ply"}]})";
  const auto files = runMeshFiles(evaluate_run, folder, "bunny");
  ASSERT_TRUE(files.has_value());
  EXPECT_EQ(files->cad, "/abs/cad.ply");
  EXPECT_EQ(files->filtered, "/abs/f.ply");
  const auto paper = runMeshFiles(R"({"datasets": [{"name": "cup_kinect_B"}]})", folder, "cup_kinect_B");
  ASSERT_TRUE(paper.has_value());
  EXPECT_EQ(paper->raw, folder.rawMesh("cup_kinect_B"));
  EXPECT_FALSE(runMeshFiles(evaluate_run, folder, "other").has_value());
  EXPECT_FALSE(runMeshFiles("not json", folder, "bunny").has_value());
  EXPECT_FALSE(runMeshFiles("", folder, "bunny").has_value());
}

TEST(RunFolder, RelativeMeshPathsAreTriedFromTheRunFolder) {
  test::ScratchDir scratch;
  std::filesystem::create_directories(scratch.path() / "meshes");
  { std::ofstream(scratch.file("meshes/raw.ply")) << "x"; }
  const RunFolder folder{scratch.path().string()};
  const auto files = runMeshFiles(
      R"({"datasets": [{"name": "d", "cad": "meshes/cad.ply", "raw": "meshes/raw.ply", "filtered": "f.ply"}]})", folder,
      "d");
  ASSERT_TRUE(files.has_value());
  EXPECT_EQ(files->raw, (scratch.path() / "meshes/raw.ply").string()) << "found in the run folder";
  EXPECT_EQ(files->cad, "meshes/cad.ply") << "found nowhere: kept as recorded";
}

TEST(RunFolder, WhatReuseMayKeep) {
  test::ScratchDir dir;
  const RunFolder folder{dir.path().string()};
  EXPECT_FALSE(folder.hasRecording("cup_kinect_B"));
  std::filesystem::create_directories(folder.datasetDir("cup_kinect_B"));
  EXPECT_FALSE(folder.hasRecording("cup_kinect_B")) << "an interrupted simulation has no manifest";
  std::ofstream(std::filesystem::path(folder.datasetDir("cup_kinect_B")) / "manifest.json") << "{}";
  EXPECT_TRUE(folder.hasRecording("cup_kinect_B"));
  std::filesystem::create_directories(folder.reconstructionDir("cup_kinect_B"));
  std::ofstream(folder.rawMesh("cup_kinect_B")) << "ply";
  EXPECT_FALSE(folder.hasReconstruction("cup_kinect_B")) << "the filtered mesh is missing";
  std::ofstream(folder.filteredMesh("cup_kinect_B")) << "ply";
  EXPECT_TRUE(folder.hasReconstruction("cup_kinect_B"));
}

}  // namespace
}  // namespace icrkit::eval
