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
  /// Kinect only: the share of the axial noise's variance that neighbouring
  /// pixels have in common and its length in pixels
  /// (SensorModel::axial_correlated_share, axial_correlation_px). 0: every
  /// pixel's noise independent, as the paper's datasets are made.
  double correlated_noise_share = 0.0;
  double correlated_noise_length_px = 3.0;  ///< [1, 64]
};

/// The paper's nine object/sensor pairs (Section II-A): SR4000 with setup A
/// on the cup and the two wooden toys; Kinect with setup B on the cup, the
/// two wooden toys, the bottle, the paper cup and the coffee pot; 36 views,
/// seed 1.
std::vector<DatasetSpec> paperDatasets();
/// "cup_kinect_B", "wooden_toy_1_sr4000_A", ...
std::string datasetName(const DatasetSpec& spec);

/// The paper datasets of these names, in the order given (all nine when
/// `names` is empty). InputError("dataset names", "", "unknown dataset
/// 'NAME' ...") for a name that is none of them.
std::vector<DatasetSpec> paperDatasets(const std::vector<std::string>& names);

/// The folder of a dataset simulated under the pose-error model given as
/// `pose_error` (its text form, parsePoseErrorModel): the dataset's name
/// for the paper's "arm", else the name and the model's text, lower case,
/// commas as underscores (cup_kinect_B_mobile, cup_kinect_B_5mm_1deg), so
/// that recordings under several models share one output folder.
std::string datasetFolderName(const DatasetSpec& spec, const std::string& pose_error);

struct SimulationReport {
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
SimulationReport simulateDataset(const DatasetSpec& spec, const std::string& directory,
                                 const ProgressCallback& progress = {});

/// What was simulated, as the JSON object `icrkit simulate` prints (keys
/// sorted): name, directory, object (its name or mesh file), sensor, setup,
/// views, seed, pose_error, object_vertices, valid_pixel_fraction,
/// object_pixel_fraction, files, time_ms.
std::string datasetRecordJson(const DatasetSpec& spec, const SimulationReport& summary);

/// The paper's nine datasets as {"datasets": [{name, object, sensor, setup,
/// views, seed}, ...]} (JSON text, keys sorted).
std::string paperDatasetsJson();

}  // namespace icrkit::sim
