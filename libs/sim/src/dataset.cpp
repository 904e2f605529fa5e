#include <icrkit/sim/dataset.hpp>

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/pose.hpp>
#include <icrkit/core/ray_caster.hpp>
#include <icrkit/sim/cad_objects.hpp>
#include <icrkit/sim/rawlog_writer.hpp>

#include <nlohmann/json.hpp>

#include "scan_rendering.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <system_error>

namespace icrkit::sim {
namespace {

namespace fs = std::filesystem;

// Per-view seeds from the dataset's seed (splitmix64): independent streams
// whatever order the views are rendered in.
std::uint64_t viewSeed(std::uint64_t seed, std::size_t view) {
  std::uint64_t x = seed + 0x9E3779B97F4A7C15ull * (view + 1);
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

StampedPose stamped(const Eigen::Isometry3d& optical, double timestamp) {
  StampedPose s;
  s.timestamp = kRawlogEpoch + timestamp;
  s.pose = mrptSensorPose(optical);
  return s;
}

nlohmann::json isometryJson(const Eigen::Isometry3d& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < 4; ++i) rows.push_back({m(i, 0), m(i, 1), m(i, 2), m(i, 3)});
  return rows;
}

nlohmann::json modelJson(const SensorModel& m) {
  const CameraIntrinsics& k = m.intrinsics;
  return {{"name", m.name},
          {"type", sensorTypeName(m.type)},
          {"width", k.width},
          {"height", k.height},
          {"fx", k.fx},
          {"fy", k.fy},
          {"cx", k.cx},
          {"cy", k.cy},
          {"distortion_k1_k2_p1_p2_k3", k.distortion},
          {"range_is_depth", m.range_is_depth},
          {"range_units_m", m.range_units},
          {"min_range_m", m.min_range},
          {"max_range_m", m.max_range}};
}

// The dataset's sensor: the type's model with the spec's correlated noise,
// checked by the model's own rules before any output is written.
SensorModel datasetSensorModel(const DatasetSpec& spec) {
  SensorModel model = sensorModel(spec.sensor);
  if (spec.correlated_noise_share == 0.0) return model;
  model.axial_correlated_share = spec.correlated_noise_share;
  model.axial_correlation_px = spec.correlated_noise_length_px;
  try {
    checkSensorModel(model);
  } catch (const InputError& error) {
    throw InputError("correlated noise", error.location(), error.detail());
  }
  return model;
}

// An existing target is replaced only when an earlier simulation made it.
void checkTarget(const fs::path& target) {
  std::error_code error;
  if (!fs::exists(target, error)) return;
  if (!fs::is_directory(target, error))
    throw InputError(target.string(), "", "exists and is not a folder; give a new output folder");
  if (!fs::is_empty(target, error) && !fs::exists(target / "manifest.json", error))
    throw InputError(target.string(), "",
                     "is a non-empty folder that holds no earlier simulation "
                     "(no manifest.json); "
                     "give a new output folder");
}

}  // namespace

std::vector<DatasetSpec> paperDatasets() {
  std::vector<DatasetSpec> specs;
  auto add = [&](const char* object, SensorType sensor, Setup setup) {
    DatasetSpec s;
    s.object = object;
    s.sensor = sensor;
    s.acquisition.setup = setup;
    s.acquisition.views = 36;
    s.acquisition.seed = 1;
    specs.push_back(s);
  };
  for (const char* o : {"cup", "wooden_toy_1", "wooden_toy_2"}) add(o, SensorType::Sr4000, Setup::A);
  for (const char* o : {"cup", "wooden_toy_1", "wooden_toy_2", "bottle", "paper_cup", "coffee_pot"})
    add(o, SensorType::Kinect, Setup::B);
  return specs;
}

std::string datasetName(const DatasetSpec& spec) {
  const std::string object = spec.mesh_path.empty() ? spec.object : fs::path(spec.mesh_path).stem().string();
  return object + "_" + sensorTypeName(spec.sensor) + "_" + setupName(spec.acquisition.setup);
}

SimulationReport simulateDataset(const DatasetSpec& spec, const std::string& directory,
                                 const ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  const fs::path target(directory);
  checkTarget(target);
  if (spec.acquisition.views <= 0)
    throw InputError("AcquisitionParameters::views", "", "expected at least one view, got " + std::to_string(spec.acquisition.views));
  const SensorModel model = datasetSensorModel(spec);

  // The staging folder first: an unwritable output fails before any work.
  fs::path staging = target;
  staging += ".partial";
  std::error_code error;
  fs::remove_all(staging, error);
  fs::create_directories(staging, error);
  if (error) throw InputError(directory, "", "cannot create the output folder: " + error.message());
  try {
    TriangleMesh object;
    if (spec.mesh_path.empty()) {
      object = makeCadObject(parseCadObject(spec.object));
    } else {
      object = io::readTriangleMesh(spec.mesh_path);
      if (object.faces.empty()) throw InputError(spec.mesh_path, "", "the mesh has no faces to scan");
    }
    const std::vector<View> views = planViews(spec.acquisition, object.vertices.bounds());
    const Scene scene = buildScene(object, spec.acquisition.setup);
    const RayCaster caster(scene.mesh);

    SimulationReport summary;
    summary.views = views.size();
    summary.object_vertices = object.vertexCount();
    summary.object_faces = object.faces.size();
    std::vector<SimulatedScan> scans;
    scans.reserve(views.size());
    std::size_t valid = 0, on_object = 0, pixels = 0;
    for (std::size_t i = 0; i < views.size(); ++i) {
      scans.push_back(
          simulateScan(caster, scene.appearance, views[i].true_camera, model, viewSeed(spec.acquisition.seed, i)));
      const SimulatedScan& s = scans.back();
      pixels += s.range.size();
      for (std::size_t p = 0; p < s.range.size(); ++p) {
        valid += s.range[p] > 0;
        on_object += s.true_face[p] >= 0 && static_cast<std::size_t>(s.true_face[p]) < scene.object_faces;
      }
      if (progress) progress("rendering " + datasetName(spec), i + 1, views.size());
    }
    summary.valid_pixel_fraction = pixels ? static_cast<double>(valid) / pixels : 0.0;
    summary.object_pixel_fraction = pixels ? static_cast<double>(on_object) / pixels : 0.0;

    writeRawlog((staging / "scans.rawlog").string(), model, scans, views);
    std::vector<StampedPose> truth, reported;
    for (const View& v : views) {
      truth.push_back(stamped(v.true_camera, v.timestamp));
      reported.push_back(stamped(v.reported_camera, v.timestamp));
    }
    writeTumTrajectory((staging / "ground_truth.txt").string(), truth);
    writeTumTrajectory((staging / "reported_poses.txt").string(), reported);
    io::writeTriangleMesh((staging / "object.ply").string(), object);
    io::writeTriangleMesh((staging / "scene.ply").string(), scene.mesh);

    const AcquisitionParameters& a = spec.acquisition;
    const PoseErrorModel& e = a.errors;
    nlohmann::json views_json = nlohmann::json::array();
    for (const View& v : views)
      views_json.push_back({{"timestamp", kRawlogEpoch + v.timestamp},
                            {"true_optical_in_object", isometryJson(v.true_camera)},
                            {"reported_optical_in_object", isometryJson(v.reported_camera)}});
    nlohmann::json manifest{
        {"format", "icrkit simulated recording 1"},
        {"object", spec.mesh_path.empty() ? spec.object : spec.mesh_path},
        {"object_vertices", summary.object_vertices},
        {"object_faces", summary.object_faces},
        {"sensor", modelJson(model)},
        {"setup", setupName(a.setup)},
        {"views", a.views},
        {"seed", a.seed},
        {"distance_m", a.distance.value_or(0.0)},  // 0: the setup's default, as manifests have always said
        {"elevation_rad",
         a.setup == Setup::A ? nlohmann::json{a.min_elevation, a.max_elevation} : nlohmann::json(a.elevation)},
        {"pose_errors",
         {{"model", e.name},
          {"noise_translation_m", e.noise_translation},
          {"noise_rotation_rad", e.noise_rotation},
          {"hand_eye_translation_m", e.hand_eye_translation},
          {"hand_eye_rotation_rad", e.hand_eye_rotation},
          {"drift_translation_m_per_view", e.drift_translation},
          {"drift_rotation_rad_per_view", e.drift_rotation}}},
        {"timestamp_epoch_s", kRawlogEpoch},
        {"files",
         {{"rawlog", "scans.rawlog"},
          {"ground_truth", "ground_truth.txt"},
          {"reported_poses", "reported_poses.txt"},
          {"object", "object.ply"},
          {"scene", "scene.ply"}}},
        {"valid_pixel_fraction", summary.valid_pixel_fraction},
        {"object_pixel_fraction", summary.object_pixel_fraction},
        {"views_detail", views_json}};
    // Written only when used: manifests of independent noise read as before.
    if (model.axial_correlated_share > 0.0)
      manifest["sensor"]["correlated_depth_noise"] = {{"share", model.axial_correlated_share},
                                                      {"length_px", model.axial_correlation_px}};
    writeFileAtomically((staging / "manifest.json").string(),
                        [&](std::ostream& out) { out << manifest.dump(2) << '\n'; }, false);
    fs::remove_all(target, error);
    fs::rename(staging, target, error);
    if (error) {
      fs::remove_all(staging, error);
      throw InputError(directory, "", "cannot move the finished recording into place");
    }
    summary.directory = target.string();
    summary.time_ms = millisecondsSince(start);
    return summary;
  } catch (...) {
    fs::remove_all(staging, error);
    throw;
  }
}

}  // namespace icrkit::sim
