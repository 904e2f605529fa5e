// Naming, choosing and describing the paper's datasets (dataset.hpp).

#include <icrkit/sim/dataset.hpp>

#include <icrkit/core/error.hpp>

#include <test_support.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace icrkit::sim {
namespace {

TEST(DatasetRecords, ChoosesThePapersDatasetsByName) {
  EXPECT_EQ(paperDatasets({}).size(), 9u);
  const std::vector<DatasetSpec> two = paperDatasets({"wooden_toy_1_sr4000_A", "cup_kinect_B"});
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(datasetName(two[0]), "wooden_toy_1_sr4000_A") << "in the order asked";
  EXPECT_EQ(two[1].sensor, SensorType::Kinect);
  const InputError error = test::expectInputError([] { paperDatasets({"cup_kinect_B", "teapot"}); });
  EXPECT_EQ(error.source(), "dataset names");
  EXPECT_NE(error.detail().find("unknown dataset 'teapot'"), std::string::npos) << error.detail();
  EXPECT_NE(error.detail().find("cup_sr4000_A"), std::string::npos) << "the known names are listed";
}

TEST(DatasetRecords, FolderNamesCarryTheirPoseErrorModel) {
  const DatasetSpec cup = paperDatasets({"cup_kinect_B"}).front();
  EXPECT_EQ(datasetFolderName(cup, "arm"), "cup_kinect_B");
  EXPECT_EQ(datasetFolderName(cup, "ARM"), "cup_kinect_B");
  EXPECT_EQ(datasetFolderName(cup, "mobile"), "cup_kinect_B_mobile");
  EXPECT_EQ(datasetFolderName(cup, "5mm,1deg"), "cup_kinect_B_5mm_1deg");
}

TEST(DatasetRecords, JsonForms) {
  const nlohmann::json list = nlohmann::json::parse(paperDatasetsJson());
  ASSERT_EQ(list["datasets"].size(), 9u);
  EXPECT_EQ(list["datasets"][0]["name"], datasetName(paperDatasets().front()));
  const DatasetSpec cup = paperDatasets({"cup_kinect_B"}).front();
  SimulationReport summary;
  summary.directory = "out/cup";
  summary.views = 36;
  const nlohmann::json record = nlohmann::json::parse(datasetRecordJson(cup, summary));
  EXPECT_EQ(record["name"], "cup_kinect_B");
  EXPECT_EQ(record["object"], "cup");
  EXPECT_EQ(record["setup"], setupName(cup.acquisition.setup));
  EXPECT_EQ(record["views"], 36);
  EXPECT_EQ(record["files"].size(), 6u);
}

}  // namespace
}  // namespace icrkit::sim
