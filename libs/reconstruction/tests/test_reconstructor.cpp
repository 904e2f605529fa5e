// The incremental Reconstructor (reconstructor.hpp): scans fed from memory
// give the file path's result, whenever update() is called; depth images as
// counts or metres and unorganised points; errors that name the scan.

#include "simulated_recordings.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/pose.hpp>
#include <icrkit/reconstruction/input/depth_image_scan.hpp>
#include <icrkit/reconstruction/input/rawlog_reader.hpp>
#include <icrkit/reconstruction/reconstructor.hpp>

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <test_support.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace icrkit::reconstruction {
namespace {

using testing_support::simulatedRecording;

void expectSameReconstruction(const ReconstructionResult& a, const ReconstructionResult& b) {
  ASSERT_EQ(a.poses.size(), b.poses.size());
  for (std::size_t i = 0; i < a.poses.size(); ++i) EXPECT_TRUE(a.poses[i].matrix() == b.poses[i].matrix()) << i;
  EXPECT_EQ(a.cloud.positions, b.cloud.positions);
  EXPECT_EQ(a.cloud.normals, b.cloud.normals);
  EXPECT_EQ(a.raw_mesh.faces, b.raw_mesh.faces);
  EXPECT_EQ(a.filtered_mesh.vertices.positions, b.filtered_mesh.vertices.positions);
  EXPECT_EQ(a.filtered_mesh.faces, b.filtered_mesh.faces);
  ASSERT_EQ(a.filters.size(), b.filters.size());
  for (std::size_t i = 0; i < a.filters.size(); ++i) {
    EXPECT_EQ(a.filters[i].object_points, b.filters[i].object_points) << i;
    EXPECT_EQ(a.filters[i].removed_jump_edges, b.filters[i].removed_jump_edges) << i;
    EXPECT_EQ(a.filters[i].removed_plane, b.filters[i].removed_plane) << i;
  }
}

TEST(Reconstructor, FedScanByScanGivesTheFilePathsResult) {
  const std::string rawlog = simulatedRecording(6, false) + "/scans.rawlog";
  ReconstructionParameters params;
  const ReconstructionResult from_file = reconstructRawlog(rawlog, params);

  Reconstructor reconstructor(params, rawlog);
  RawlogReader reader(rawlog);
  while (auto scan = reader.next()) reconstructor.add(std::move(*scan));
  EXPECT_EQ(reconstructor.scanCount(), 6u);
  EXPECT_FALSE(reconstructor.upToDate());
  const ReconstructionResult& fed = reconstructor.update();
  EXPECT_TRUE(reconstructor.upToDate());
  expectSameReconstruction(fed, from_file);
  EXPECT_GT(fed.raw_mesh.faces.size(), 1000u);
  // Kept single precision where MRPT's unprojection is: about 16 bytes a point.
  std::size_t valid = 0;
  for (const ScanFilterRecord& r : fed.filters) valid += r.valid_pixels;
  EXPECT_LT(reconstructor.storedBytes(), 6 * 640 * 480 * sizeof(float) + 20 * valid);
}

TEST(Reconstructor, ResultDoesNotDependOnWhenUpdateIsCalled) {
  const std::vector<RangeScan> scans = readAllScans(simulatedRecording(6, false) + "/scans.rawlog");
  ReconstructionParameters params;
  params.make_meshes = false;
  Reconstructor all_at_once(params);
  for (const RangeScan& scan : scans) all_at_once.add(scan);
  const ReconstructionResult& reference = all_at_once.update();

  Reconstructor as_they_come(params);
  for (std::size_t i = 0; i < scans.size(); ++i) {
    as_they_come.add(scans[i]);
    if (i == 2) {
      const ReconstructionResult& early = as_they_come.update();
      EXPECT_EQ(early.poses.size(), 3u);
      EXPECT_GT(early.cloud.positions.size(), 1000u);
    }
  }
  EXPECT_FALSE(as_they_come.upToDate());
  expectSameReconstruction(as_they_come.update(), reference);
}

// Registered as the scans arrive (SequenceRegistrationParameters::
// incremental): add() does the registration's per-view work, update()
// solves from there, and the result is still a function of the scans alone.
TEST(Reconstructor, RegisteredAsTheScansArriveDoesNotDependOnWhenUpdateIsCalled) {
  const std::vector<RangeScan> scans = readAllScans(simulatedRecording(6, false) + "/scans.rawlog");
  ReconstructionParameters params;
  params.make_meshes = false;
  params.registration.incremental = true;
  Reconstructor all_at_once(params);
  for (const RangeScan& scan : scans) all_at_once.add(scan);
  const ReconstructionResult& reference = all_at_once.update();
  EXPECT_EQ(reference.registration.model_alignment_accepted.size(), params.registration.model_alignment_resolutions.size());

  Reconstructor as_they_come(params);
  for (std::size_t i = 0; i < scans.size(); ++i) {
    as_they_come.add(scans[i]);
    // Two views cannot place the crop box by themselves yet (fewer than
    // three): registered from scratch for this call, nothing kept.
    if (i == 1) {
      EXPECT_EQ(as_they_come.update().poses.size(), 2u);
    }
    if (i == 3) {
      EXPECT_EQ(as_they_come.update().poses.size(), 4u);
    }
  }
  expectSameReconstruction(as_they_come.update(), reference);
  // The file path with the same parameters is the same Reconstructor.
  expectSameReconstruction(reconstructRawlog(simulatedRecording(6, false) + "/scans.rawlog", params), reference);

  // Close to all views registered together at the end.
  params.registration.incremental = false;
  Reconstructor together(params);
  for (const RangeScan& scan : scans) together.add(scan);
  const ReconstructionResult& batch = together.update();
  // The box as the scans arrive is placed from the first views whose axes
  // spread, the batch's from all of them: the same size, centres close.
  EXPECT_TRUE(reference.crop_box_automatic);
  EXPECT_TRUE(batch.crop_box_automatic);
  EXPECT_TRUE(batch.crop_box.sizes().isApprox(reference.crop_box.sizes(), 1e-12));
  EXPECT_LT((batch.crop_box.center() - reference.crop_box.center()).norm(), 0.01);
  const Eigen::Vector3d centre = reference.crop_box.center();
  for (std::size_t i = 0; i < scans.size(); ++i)
    EXPECT_LT((reference.poses[i] * batch.poses[i].inverse() * centre - centre).norm(), 1.5e-3) << "view " << i;
}

TEST(Reconstructor, RegisteredAsTheScansArriveReportsAViewWithoutObjectAtUpdate) {
  const std::vector<RangeScan> scans = readAllScans(simulatedRecording(6, false) + "/scans.rawlog");
  ReconstructionParameters params;
  params.make_meshes = false;
  params.registration.incremental = true;
  // Far from the object: nothing of any scan inside.
  params.crop_box = Eigen::AlignedBox3d(Eigen::Vector3d(10, 10, 10), Eigen::Vector3d(11, 11, 11));
  Reconstructor reconstructor(params, "stream");
  for (const RangeScan& scan : scans) EXPECT_NO_THROW(reconstructor.add(scan));
  try {
    reconstructor.update();
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scan 0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("crop box"), std::string::npos) << e.what();
  }
}

// Parameters are checked when the Reconstructor is made, before any scan
// is stored: registering as the scans arrive would otherwise meet a bad
// value only at the first add().
TEST(Reconstructor, RejectsBadRegistrationParametersAtConstruction) {
  ReconstructionParameters params;
  params.registration.incremental = true;
  params.registration.model_voxel_size = -1.0;
  try {
    Reconstructor reconstructor(params, "stream");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("model_voxel_size"), std::string::npos) << e.what();
  }
  params.registration.model_voxel_size = SequenceRegistrationParameters{}.model_voxel_size;
  params.register_scans = false;
  try {
    Reconstructor reconstructor(params, "stream");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("incremental"), std::string::npos) << e.what();
  }
}

// Registering as the scans arrive keeps each view's registration input:
// storedBytes() counts it.
TEST(Reconstructor, StoredBytesCountTheRegistrationAsTheScansArrive) {
  const std::vector<RangeScan> scans = readAllScans(simulatedRecording(6, false) + "/scans.rawlog");
  ReconstructionParameters params;
  params.make_meshes = false;
  Reconstructor batch(params);
  params.registration.incremental = true;
  Reconstructor incremental(params);
  for (const RangeScan& scan : scans) {
    batch.add(scan);
    incremental.add(scan);
  }
  // The crop box is placed from the third view on; each view registered
  // since then adds its reduced points, NDT and ICP inputs.
  EXPECT_GT(incremental.storedBytes(), batch.storedBytes() + 6 * 1000 * sizeof(Eigen::Vector3d));
}

// A synthetic 64 x 48 view of a tilted plane 0.8-0.9 m away.
std::vector<std::uint16_t> planeInMillimetres(int width, int height) {
  std::vector<std::uint16_t> counts(static_cast<std::size_t>(width) * height);
  for (int r = 0; r < height; ++r)
    for (int c = 0; c < width; ++c) counts[static_cast<std::size_t>(r) * width + c] = static_cast<std::uint16_t>(800 + c + r);
  counts[5] = 0;  // no return
  return counts;
}

CameraIntrinsics smallCamera() {
  CameraIntrinsics k;
  k.width = 64;
  k.height = 48;
  k.fx = k.fy = 60.0;
  k.cx = 31.5;
  k.cy = 23.5;
  return k;
}

TEST(DepthImageScan, CountsAndMetresGiveTheSamePoints) {
  const CameraIntrinsics k = smallCamera();
  const std::vector<std::uint16_t> counts = planeInMillimetres(k.width, k.height);
  std::vector<float> metres(counts.size());
  for (std::size_t i = 0; i < counts.size(); ++i) metres[i] = counts[i] ? counts[i] * 1e-3f : std::nanf("");
  DepthImageMeta meta;
  meta.intrinsics = k;
  Eigen::Isometry3d optical = Eigen::Isometry3d::Identity();
  optical.translation() = Eigen::Vector3d(0.1, -0.2, 0.3);
  meta.sensor_pose = opticalToSensorPose(optical);

  DepthImageView from_counts;
  from_counts.width = k.width;
  from_counts.height = k.height;
  from_counts.counts = counts.data();
  from_counts.depth_scale = 1000.0;
  DepthImageView from_metres = from_counts;
  from_metres.counts = nullptr;
  from_metres.metres = metres.data();
  const RangeScan a = scanFromDepthImage(from_counts, meta, 0, "counts");
  const RangeScan b = scanFromDepthImage(from_metres, meta, 0, "metres");
  EXPECT_EQ(a.points.size(), counts.size() - 1);
  EXPECT_EQ(a.pixels, b.pixels);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) EXPECT_LT((a.points[i] - b.points[i]).norm(), 2e-6) << i;
  // The principal ray of the optical frame is the camera's +z: pixel (23,
  // 31) near the centre lies 0.854 m along it, beside the camera.
  const std::size_t centre = 23 * 64 + 31;
  const auto it = std::find(a.pixels.begin(), a.pixels.end(), centre);
  ASSERT_NE(it, a.pixels.end());
  const Eigen::Vector3d p = optical.inverse() * a.points[static_cast<std::size_t>(it - a.pixels.begin())];
  EXPECT_NEAR(p.z(), 0.854, 1e-6);
  EXPECT_NEAR(p.x(), -0.5 * 0.854 / 60.0, 1e-6);
  EXPECT_NEAR(p.y(), -0.5 * 0.854 / 60.0, 1e-6);

  // A row stride longer than the row: the same image.
  std::vector<std::uint16_t> padded(static_cast<std::size_t>(k.height) * (k.width + 3), 7);
  for (int r = 0; r < k.height; ++r)
    for (int c = 0; c < k.width; ++c) padded[static_cast<std::size_t>(r) * (k.width + 3) + c] = counts[static_cast<std::size_t>(r) * k.width + c];
  DepthImageView strided = from_counts;
  strided.counts = padded.data();
  strided.row_stride = static_cast<std::size_t>(k.width + 3);
  EXPECT_EQ(scanFromDepthImage(strided, meta, 0, "strided").points, a.points);
}

TEST(DepthImageScan, BadImagesNameTheScan) {
  const CameraIntrinsics k = smallCamera();
  std::vector<std::uint16_t> counts = planeInMillimetres(k.width, k.height);
  DepthImageMeta meta;
  meta.intrinsics = k;
  DepthImageView view;
  view.width = k.width;
  view.height = k.height - 1;
  view.counts = counts.data();
  auto message = [&](const DepthImageView& v, const DepthImageMeta& m) -> std::string {
    try {
      scanFromDepthImage(v, m, 4, "camera");
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_NE(message(view, meta).find("scan 4"), std::string::npos) << message(view, meta);
  view.height = k.height;
  view.depth_scale = 0.0;
  EXPECT_NE(message(view, meta).find("depth scale"), std::string::npos);
  view.depth_scale = 1000.0;
  std::vector<float> metres(counts.size(), 1.0f);
  metres[17] = std::numeric_limits<float>::infinity();
  DepthImageView both = view;
  both.metres = metres.data();
  EXPECT_NE(message(both, meta).find("one depth image"), std::string::npos);
  DepthImageView infinite = view;
  infinite.counts = nullptr;
  infinite.metres = metres.data();
  EXPECT_NE(message(infinite, meta).find("pixel (0, 17)"), std::string::npos) << message(infinite, meta);
  DepthImageMeta no_focal = meta;
  no_focal.intrinsics.fx = 0.0;
  EXPECT_NE(message(view, no_focal).find("focal"), std::string::npos);
}

TEST(Reconstructor, UnorganisedPointsReconstructLikeTheImages) {
  const std::vector<RangeScan> scans = readAllScans(simulatedRecording(6, false) + "/scans.rawlog");
  ReconstructionParameters params;
  params.make_meshes = false;
  Reconstructor images(params), points(params);
  for (const RangeScan& scan : scans) {
    images.add(scan);
    PointScanMeta meta;
    meta.timestamp = scan.timestamp;
    Eigen::Isometry3d optical = scan.sensor_pose;
    optical.linear() = scan.sensor_pose.linear() * mrptSensorAxesInOptical().transpose();
    meta.optical_pose = optical;
    std::vector<Eigen::Vector3d> local;
    const Eigen::Isometry3d to_camera = optical.inverse();
    for (const Eigen::Vector3d& p : scan.points) local.push_back(to_camera * p);
    local.push_back(Eigen::Vector3d::Constant(std::nan("")));  // no return
    points.addPoints(local, meta);
  }
  const ReconstructionResult& a = images.update();
  const ReconstructionResult& b = points.update();
  EXPECT_EQ(b.poses.size(), a.poses.size());
  // No jump-edge filter without a pixel grid: a few more points, all on the
  // surface the image path found.
  EXPECT_GE(b.cloud.positions.size(), a.cloud.positions.size() * 9 / 10);
  const KdTree tree(a.cloud.positions);
  std::vector<double> distances;
  for (const Eigen::Vector3d& p : b.cloud.positions) distances.push_back(tree.nearest(p, 1).front().distance);
  std::nth_element(distances.begin(), distances.begin() + distances.size() / 2, distances.end());
  EXPECT_LT(distances[distances.size() / 2], 1e-3);
}

TEST(Reconstructor, BadInputNamesTheScan) {
  Reconstructor reconstructor;
  EXPECT_THROW(reconstructor.update(), InputError);
  PointScanMeta meta;
  try {
    reconstructor.addPoints({Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, std::numeric_limits<double>::infinity(), 1)},
                            meta);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scan 0 point 1"), std::string::npos) << e.what();
  }
  RangeScan broken;
  broken.width = 2;
  broken.height = 2;
  broken.range.assign(3, 1.0f);
  EXPECT_THROW(reconstructor.add(broken), InputError);
  EXPECT_EQ(reconstructor.scanCount(), 0u);
  ReconstructionParameters bad;
  bad.fusion.resolution = -1.0;
  EXPECT_THROW(Reconstructor{bad}, InputError);
}

// The shared real recording's depth images, decoded here and fed as arrays
// with their reported optical poses: the TUM folder's reconstruction.
TEST(Reconstructor, RealDepthImagesFromMemoryGiveTheFoldersCloud) {
  const std::string folder = test::sharedData("primesense-bunny/tum");
  if (!std::filesystem::exists(folder + "/depth.txt")) GTEST_SKIP() << "shared test data not found: " << folder;
  ReconstructionParameters params;
  params.make_meshes = false;
  params.pose_file = folder + "/reported.txt";
  CameraIntrinsics k;
  k.fx = 542.0;
  k.fy = 540.5;
  k.cx = 320.0;
  k.cy = 240.0;
  params.depth_camera.intrinsics = k;
  params.depth_camera.depth_scale = 1000.0;
  const ReconstructionResult from_folder = reconstructRawlog(folder, params);

  const std::vector<DepthFrame> frames = readDepthList(folder + "/depth.txt");
  std::vector<std::uint8_t> normalised;
  const std::vector<StampedPose> poses = readTumTrajectory(folder + "/reported.txt", &normalised);
  ASSERT_EQ(frames.size(), poses.size());
  ReconstructionParameters memory_params = params;
  memory_params.pose_file.clear();
  Reconstructor reconstructor(memory_params);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const cv::Mat image = cv::imread(frames[i].path, cv::IMREAD_ANYDEPTH);
    ASSERT_EQ(image.type(), CV_16UC1);
    DepthImageView view;
    view.width = image.cols;
    view.height = image.rows;
    view.counts = image.ptr<std::uint16_t>(0);
    view.depth_scale = 1000.0;
    DepthImageMeta meta;
    meta.intrinsics = k;
    meta.intrinsics.width = image.cols;
    meta.intrinsics.height = image.rows;
    meta.pose_normalised = normalised[i] != 0;
    meta.sensor_pose = opticalToSensorPose(poses[i].pose);
    meta.timestamp = frames[i].timestamp;
    reconstructor.addDepthImage(view, meta);
  }
  const ReconstructionResult& fed = reconstructor.update();
  ASSERT_EQ(fed.poses.size(), 18u);
  for (std::size_t i = 0; i < fed.poses.size(); ++i)
    EXPECT_LT((fed.reported_poses[i].matrix() - from_folder.reported_poses[i].matrix()).cwiseAbs().maxCoeff(), 1e-12)
        << i;
  EXPECT_EQ(fed.cloud.positions.size(), from_folder.cloud.positions.size());
  EXPECT_EQ(fed.cloud.positions, from_folder.cloud.positions);
}

}  // namespace
}  // namespace icrkit::reconstruction
