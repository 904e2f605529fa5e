// icrkit.Reconstructor: scans from NumPy arrays, as they arrive
// (reconstructor.hpp). Depth images are read in place (no copy) when their
// rows are contiguous; the work runs with the GIL released.

#include "arrays.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/pose.hpp>
#include <icrkit/core/atomic_file.hpp>
#include <icrkit/reconstruction/reconstruction_outputs.hpp>
#include <icrkit/reconstruction/reconstructor.hpp>

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <mutex>
#include <utility>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::python {

namespace py = pybind11;
using reconstruction::Reconstructor;

namespace {

Eigen::Isometry3d poseFromPython(const py::handle& object, const char* what) {
  const py::array_t<double, py::array::c_style | py::array::forcecast> a =
      py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(object);
  if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
    throw py::value_error(std::string(what) + ": expected a 4x4 camera-to-object matrix (optical axes)");
  Eigen::Matrix4d m;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m(i, j) = a.at(i, j);
  if (!m.allFinite() || m.row(3) != Eigen::RowVector4d(0, 0, 0, 1))
    throw py::value_error(std::string(what) + ": expected finite values and a last row 0 0 0 1");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.matrix() = m;
  return pose;
}

CameraIntrinsics intrinsicsFromPython(const std::vector<double>& values, const std::optional<std::vector<double>>& distortion) {
  if (values.size() != 4) throw py::value_error("intrinsics: expected (fx, fy, cx, cy) in pixels");
  CameraIntrinsics k;
  k.fx = values[0];
  k.fy = values[1];
  k.cx = values[2];
  k.cy = values[3];
  if (distortion) {
    if (distortion->size() != 5) throw py::value_error("distortion: expected (k1, k2, p1, p2, k3)");
    for (std::size_t i = 0; i < 5; ++i) k.distortion[i] = (*distortion)[i];
  }
  return k;
}

ProgressCallback progressFromPython(const py::object& progress) {
  if (progress.is_none()) return {};
  return [progress](const std::string& stage, std::size_t done, std::size_t total) {
    py::gil_scoped_acquire acquire;  // called from worker threads
    progress(stage, done, total);
  };
}

// The object Python holds: the reconstructor and what its record needs. A
// ROS callback thread may add while another asks for meshes: every call
// takes the mutex, always after releasing the GIL (the progress callback
// takes the GIL while the mutex is held), and copies what it returns before
// letting go, since the next add() drops the result.
struct PyReconstructor {
  reconstruction::ReconstructionParameters params;
  Reconstructor reconstructor;
  std::mutex mutex;

  explicit PyReconstructor(reconstruction::ReconstructionParameters p)
      : params(p), reconstructor(std::move(p), "scans") {}

  template <typename Take>
  auto withResult(const py::object& progress, Take&& take) {
    const ProgressCallback callback = progressFromPython(progress);
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex);
    return take(reconstructor.update(callback));
  }

  template <typename Do>
  auto locked(Do&& action) {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex);
    return action(reconstructor);
  }
};


}  // namespace

void bindReconstructor(py::module_& m) {
  m.def(
      "read_tum_poses",
      [](const std::string& path) {
        const std::vector<StampedPose> poses = readTumTrajectory(path);
        std::vector<Eigen::Isometry3d> matrices;
        py::array_t<double> stamps(static_cast<py::ssize_t>(poses.size()));
        for (std::size_t i = 0; i < poses.size(); ++i) {
          stamps.mutable_at(static_cast<py::ssize_t>(i)) = poses[i].timestamp;
          matrices.push_back(poses[i].pose);
        }
        return py::make_tuple(stamps, posesArray(matrices));
      },
      py::arg("path"),
      "A TUM trajectory (`timestamp tx ty tz qx qy qz qw` lines) as (timestamps (K,), poses (K, 4, 4)), read as "
      "`icrkit reconstruct --poses` reads it (quaternions normalised). ValueError naming the line otherwise.");

  py::class_<PyReconstructor>(m, "Reconstructor",
                              "The reconstruction of `icrkit reconstruct` fed one scan at a time from NumPy arrays "
                              "(docs/python.md). Scans are filtered as they arrive; registration, fusion and meshes "
                              "run on demand (cloud(), meshes(), report(), poses()) for the scans so far and are "
                              "kept until the next add. Poses are 4x4 camera-to-object matrices in the camera's "
                              "optical axes (x right, y down, z forward: ROS, TUM, OpenCV).")
      .def(py::init([](std::optional<std::vector<double>> crop_box, double auto_crop_half_size, bool register_scans,
                       const std::string& smoothing, bool meshes, bool raw_mesh, bool register_as_scans_arrive,
                       std::optional<std::vector<double>> up, bool joint_refinement) {
             reconstruction::ReconstructionParameters params;
             if (crop_box) {
               if (crop_box->size() != 6)
                 throw py::value_error("crop_box: expected (xmin, ymin, zmin, xmax, ymax, zmax) in metres");
               params.crop_box = Eigen::AlignedBox3d(Eigen::Vector3d((*crop_box)[0], (*crop_box)[1], (*crop_box)[2]),
                                                     Eigen::Vector3d((*crop_box)[3], (*crop_box)[4], (*crop_box)[5]));
             }
             params.auto_crop_half_size = auto_crop_half_size;
             if (up) {
               const Eigen::Vector3d v = up->size() == 3 ? Eigen::Vector3d((*up)[0], (*up)[1], (*up)[2])
                                                         : Eigen::Vector3d::Zero();
               if (!v.allFinite() || !(v.norm() > 1e-9))
                 throw py::value_error("up: expected a non-zero, finite direction (x, y, z) in the object frame");
               params.up = v.normalized();
             }
             params.register_scans = register_scans;
             params.registration.incremental = register_as_scans_arrive;
             params.registration.joint_refinement = joint_refinement;
             if (smoothing == "paper")
               params.smoothing.max_normal_angle = M_PI;
             else if (smoothing != "feature")
               throw py::value_error("smoothing: expected 'feature' (the default) or 'paper'");
             params.make_meshes = meshes;
             params.make_raw_mesh = raw_mesh;
             return new PyReconstructor(std::move(params));
           }),
           py::arg("crop_box") = py::none(), py::arg("auto_crop_half_size") = 0.15, py::arg("register") = true,
           py::arg("smoothing") = "feature", py::arg("meshes") = true, py::arg("raw_mesh") = true,
           py::arg("register_as_scans_arrive") = false, py::arg("up") = py::none(), py::arg("joint_refinement") = true,
           "`crop_box`: the object's region (object frame, metres); None: a cube of 2 x auto_crop_half_size where "
           "the views' optical axes meet. `register`: false keeps the given poses. `smoothing`: 'feature' "
           "(one-sided windows, the default of `icrkit reconstruct`) or 'paper' (Algorithm 1 as published). "
           "`raw_mesh`: false skips the paper's raw baseline (meshes() then gives (None, filtered)): a robot grasps "
           "the filtered mesh, which then comes a third sooner. `register_as_scans_arrive`: each add registers its view "
           "with the earlier ones (the GIL released), so that cloud()/meshes() after the last scan only close the loop, "
           "solve the pose graph, run the later multiway rounds and the joint refinement, fuse and mesh; the result then differs from `icrkit reconstruct` without "
           "--register-as-scans-arrive (docs/reconstruction.md, \"Streaming\"). `up`: the object frame's up "
           "direction, where the support plane is searched; None: estimated from the poses (`icrkit reconstruct "
           "--up`). `joint_refinement`: false keeps the pose graph's poses (`icrkit reconstruct --no-joint-refinement`).")
      .def(
          "add_depth",
          [](PyReconstructor& self, const py::array& depth, const std::vector<double>& intrinsics,
             const py::handle& pose, double timestamp, double depth_scale,
             const std::optional<std::vector<double>>& distortion, double max_range) {
            if (depth.ndim() != 2) throw py::value_error("depth: expected an (H, W) array, got a " + describe(depth));
            const bool counts = depth.dtype().is(py::dtype::of<std::uint16_t>());
            if (!counts && !depth.dtype().is(py::dtype::of<float>()))
              throw py::value_error("depth: expected uint16 counts or float32 metres, got a " + describe(depth) +
                                    " (convert with depth.astype(numpy.float32))");
            // In place when each row is contiguous; otherwise one packed copy.
            const py::ssize_t item = depth.itemsize();
            py::array data = depth;
            if (depth.strides(1) != item || depth.strides(0) % item != 0 || depth.strides(0) < depth.shape(1) * item)
              data = py::array::ensure(depth, py::array::c_style);
            reconstruction::DepthImageView view;
            view.height = static_cast<int>(data.shape(0));
            view.width = static_cast<int>(data.shape(1));
            view.row_stride = static_cast<std::size_t>(data.strides(0) / item);
            view.depth_scale = depth_scale;
            if (counts)
              view.counts = static_cast<const std::uint16_t*>(data.data());
            else
              view.metres = static_cast<const float*>(data.data());
            reconstruction::DepthImageMeta meta;
            meta.intrinsics = intrinsicsFromPython(intrinsics, distortion);
            meta.intrinsics.width = view.width;
            meta.intrinsics.height = view.height;
            meta.sensor_pose = reconstruction::opticalToSensorPose(poseFromPython(pose, "pose"));
            meta.timestamp = timestamp;
            meta.max_range = max_range;
            self.locked([&](Reconstructor& r) { r.addDepthImage(view, meta); });
          },
          py::arg("depth"), py::arg("intrinsics"), py::arg("pose"), py::arg("timestamp") = 0.0,
          py::arg("depth_scale") = 1000.0, py::arg("distortion") = py::none(), py::arg("max_range") = 0.0,
          "Adds a depth image: (H, W) uint16 counts (`depth_scale` per metre; 1000: millimetres) or float32 metres; "
          "0 or NaN: no return. `intrinsics`: (fx, fy, cx, cy) pixels; `distortion`: (k1, k2, p1, p2, k3); "
          "`pose`: 4x4 camera-to-object, optical axes. Read in place, not copied, when its rows are contiguous.")
      .def(
          "add_points",
          [](PyReconstructor& self, const py::handle& points, const py::handle& pose, double timestamp,
             double max_range) {
            const py::array_t<double, py::array::c_style | py::array::forcecast> a =
                py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(points);
            if (!a || a.ndim() != 2 || a.shape(1) != 3)
              throw py::value_error("points: expected an (N, 3) array of metres in the camera's optical frame");
            std::vector<Eigen::Vector3d> local(static_cast<std::size_t>(a.shape(0)));
            const double* p = a.data();
            for (std::size_t i = 0; i < local.size(); ++i) local[i] = Eigen::Vector3d(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
            reconstruction::PointScanMeta meta;
            meta.optical_pose = poseFromPython(pose, "pose");
            meta.timestamp = timestamp;
            meta.max_range = max_range;
            self.locked([&](Reconstructor& r) { r.addPoints(local, meta); });
          },
          py::arg("points"), py::arg("pose"), py::arg("timestamp") = 0.0, py::arg("max_range") = 0.0,
          "Adds unorganised points ((N, 3), metres, the camera's optical frame; NaN rows: no return) seen from "
          "`pose` (4x4 camera-to-object). No jump-edge filter: it needs an image grid.")
      .def("__len__", [](PyReconstructor& self) { return self.locked([](Reconstructor& r) { return r.scanCount(); }); })
      .def_property_readonly(
          "up_to_date", [](PyReconstructor& self) { return self.locked([](Reconstructor& r) { return r.upToDate(); }); },
          "True when the last result still holds every scan added.")
      .def_property_readonly(
          "stored_bytes",
          [](PyReconstructor& self) { return self.locked([](Reconstructor& r) { return r.storedBytes(); }); },
          "Memory held for the scans added so far (bytes).")
      .def(
          "cloud",
          [](PyReconstructor& self, const py::object& progress) {
            return self.withResult(progress, [](const reconstruction::ReconstructionResult& r) { return r.cloud; });
          },
          py::arg("progress") = py::none(),
          "The fused object cloud (PointCloud with normals and the attributes view, pixel, viewpoint_x/y/z). "
          "`progress(stage, done, total)` is called from worker threads.")
      .def(
          "meshes",
          [](PyReconstructor& self, const py::object& progress) {
            if (!self.params.make_meshes) throw py::value_error("meshes: this Reconstructor was made with meshes=False");
            auto meshes = self.withResult(progress, [](const reconstruction::ReconstructionResult& r) {
              return std::make_pair(r.raw_mesh, r.filtered_mesh);
            });
            if (!self.params.make_raw_mesh) return py::make_tuple(py::none(), std::move(meshes.second));
            return py::make_tuple(std::move(meshes.first), std::move(meshes.second));
          },
          py::arg("progress") = py::none(),
          "(raw, filtered) TriangleMesh: ball pivoting of the fused cloud and of its 3D-NDT smoothed layer "
          "(the filtered mesh carries cardinality, flatness, displacement and excluded).")
      .def(
          "poses",
          [](PyReconstructor& self, bool reported, const py::object& progress) {
            std::vector<Eigen::Isometry3d> poses = self.withResult(
                progress, [&](const reconstruction::ReconstructionResult& r) { return reported ? r.reported_poses : r.poses; });
            // Back to the optical axes they came in with.
            for (Eigen::Isometry3d& pose : poses)
              pose.linear() = pose.linear() * reconstruction::mrptSensorAxesInOptical().transpose();
            return posesArray(poses);
          },
          py::arg("reported") = false, py::arg("progress") = py::none(),
          "(K, 4, 4) camera-to-object poses in optical axes: registered, or as given (`reported`).")
      .def(
          "report",
          [](PyReconstructor& self, const py::object& progress) {
            const std::string text = self.withResult(progress, [&](const reconstruction::ReconstructionResult& r) {
              reconstruction::ReconstructionRecordInput input;
              input.input = "scans";
              input.input_format = "memory";
              return reconstruction::reconstructionRecordJson(r, self.params, input);
            });
            return py::module_::import("json").attr("loads")(text);
          },
          py::arg("progress") = py::none(), "The record `icrkit reconstruct` writes as reconstruction.json, as a dict.")
      .def(
          "write",
          [](PyReconstructor& self, const std::string& directory, const py::object& progress) {
            self.withResult(progress, [&](const reconstruction::ReconstructionResult& r) {
              reconstruction::ReconstructionRecordInput input;
              input.input = "scans";
              input.input_format = "memory";
              input.output = directory;
              reconstruction::writeReconstructionFiles(directory, r, self.params.make_meshes);
              writeFileAtomically(directory + "/reconstruction.json",
                                  reconstruction::reconstructionRecordJson(r, self.params, input) + "\n");
              return 0;
            });
          },
          py::arg("directory"), py::arg("progress") = py::none(),
          "Writes the files of `icrkit reconstruct -o DIRECTORY` (cloud.ply, raw.ply, filtered.ply, poses.txt, "
          "reconstruction.json), each atomically.");
}

}  // namespace icrkit::python
