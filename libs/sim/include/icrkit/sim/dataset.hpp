#pragma once
/// \file
/// A simulated recording: an object (one of the paper's CAD objects or any
/// mesh), a sensor, a setup, views and a seed, written to a folder that the
/// reconstruction reads like a real recording. Folder contents
/// (docs/rawlog.md):
///   scans.rawlog        gzip MRPT rawlog of CObservation3DRangeScan
///   ground_truth.txt    true sensor poses, TUM, MRPT sensor axes, object frame
///   reported_poses.txt  the robot-reported poses written into the rawlog (TUM)
///   object.ply          the object's mesh in the object frame
///   scene.ply           object plus the setup's fixtures (table or support)
///   manifest.json       object, sensor, setup, seed and every parameter

#include <icrkit/core/progress.hpp>
#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/sim/acquisition.hpp>
#include <icrkit/sim/range_sensor.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace icrkit::sim {

struct DatasetSpec {
  std::string object = "cup";  ///< a CAD object name (cadObjectNames()); ignored when `mesh_path` is set
  std::string mesh_path;       ///< a user mesh (PLY/OBJ) to scan instead, in metres
  SensorType sensor = SensorType::Kinect;
  AcquisitionParameters acquisition;  ///< setup, views, seed, distances, pose errors
};

/// The paper's nine object/sensor pairs (Section II-A): SR4000 with setup A
/// on the cup and the two wooden toys; Kinect with setup B on the cup, the
/// two wooden toys, the bottle, the paper cup and the coffee pot; 36 views,
/// seed 1.
std::vector<DatasetSpec> paperDatasets();
/// "cup_kinect_B", "wooden_toy_1_sr4000_A", ...
std::string datasetName(const DatasetSpec& spec);

struct DatasetSummary {
  std::string directory;
  std::size_t views = 0;
  std::size_t object_vertices = 0, object_faces = 0;
  double valid_pixel_fraction = 0.0;   ///< pixels with a return, over all views
  double object_pixel_fraction = 0.0;  ///< pixels whose true surface is the object
  double time_ms = 0.0;
};

/// Simulates and writes the recording into `directory` (created; an
/// existing folder is only replaced when it holds an earlier simulation,
/// i.e. a manifest.json). Everything is written into a temporary sibling
/// folder first and renamed into place at the end. Throws InputError for an
/// unknown object, unreadable mesh, bad parameters or an unwritable folder.
DatasetSummary simulateDataset(const DatasetSpec& spec, const std::string& directory,
                               const ProgressCallback& progress = {});

}  // namespace icrkit::sim
