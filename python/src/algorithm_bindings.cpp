// The algorithms a researcher scripts: smoothing, ball pivoting, ICRs and
// grasp sampling. Inputs are converted (and checked) while holding the GIL;
// the computation runs without it, so other Python threads keep going.

#include "arrays.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/icr/grasp_sampling.hpp>
#include <icrkit/icr/independent_contact_regions.hpp>
#include <icrkit/planning/grasp_planner.hpp>
#include <icrkit/planning/plan_file.hpp>
#include <icrkit/icr/patch_contacts.hpp>
#include <icrkit/ndt/preselection.hpp>
#include <icrkit/ndt/smoothing.hpp>
#include <icrkit/reconstruction/fusion/octree_fusion.hpp>
#include <icrkit/reconstruction/meshing/ball_pivoting.hpp>
#include <icrkit/reconstruction/reconstruction_pipeline.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>

namespace icrkit::python {

namespace {

PointCloud asCloud(const py::handle& points, const py::handle& normals) {
  if (py::isinstance<PointCloud>(points)) {
    PointCloud cloud = points.cast<PointCloud>();
    if (!normals.is_none()) cloud.normals = cloudFromPython(points.attr("points"), normals).normals;
    return cloud;
  }
  return cloudFromPython(points, normals);
}

icr::ContactModel contactModel(const std::string& model, double mu, int edges, double mu_t) {
  icr::ContactModel m;
  m.type = icr::parseContactType(model);
  m.friction = mu;
  m.cone_edges = edges;
  m.torsional_friction = mu_t;
  m.validate();
  return m;
}

std::vector<std::uint8_t> exclusionMask(const TriangleMesh& mesh, const py::handle& excluded) {
  if (excluded.is_none()) return icr::exclusionMaskOf(mesh);
  const py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast> a =
      py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(excluded);
  if (!a || a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != mesh.vertexCount())
    throw py::value_error("excluded: expected one flag per vertex (" + std::to_string(mesh.vertexCount()) + ")");
  return std::vector<std::uint8_t>(a.data(), a.data() + a.shape(0));
}

py::dict resultToDict(const icr::IcrResult& r) {
  py::list regions;
  for (const icr::ContactRegion& region : r.regions) {
    py::dict d;
    d["finger"] = region.finger;
    d["contact"] = region.contact;
    d["vertices"] = py::array_t<int>(static_cast<py::ssize_t>(region.vertices.size()), region.vertices.data());
    d["area_m2"] = region.area_m2;
    d["recommended"] = py::dict(py::arg("vertex") = region.recommended.vertex,
                                py::arg("depth_m") = region.recommended.depth_m);
    regions.append(d);
  }
  py::dict out;
  out["epsilon"] = r.epsilon;
  out["lambda_m"] = r.lambda_m;
  out["tws_radius"] = r.tws_radius;
  out["gws_facets"] = r.gws_facets;
  out["regions"] = regions;
  out["vertices_tested"] = r.vertices_tested;
  out["time_ms"] = py::dict(py::arg("hull") = r.timings.hull_ms, py::arg("zones") = r.timings.zones_ms,
                            py::arg("growth") = r.timings.growth_ms, py::arg("total") = r.timings.total_ms);
  return out;
}

py::dict meshingReport(const reconstruction::BallPivotingReport& r) {
  return py::dict(py::arg("triangles") = r.triangles, py::arg("used_points") = r.used_points,
                  py::arg("boundary_loops") = r.boundary_loops, py::arg("components") = r.components,
                  py::arg("non_manifold_edges") = r.non_manifold_edges, py::arg("reinserted_points") = r.reinserted_points,
                  py::arg("closed_holes") = r.closed_holes, py::arg("folded_holes") = r.folded_holes);
}


}  // namespace

void bindAlgorithms(py::module_& m) {
  m.def(
      "reconstruct",
      [](const std::string& input, const std::string& poses, std::optional<std::vector<double>> intrinsics,
         std::optional<double> depth_scale, const py::object& progress) {
        reconstruction::ReconstructionParameters params;
        params.pose_file = poses;
        if (intrinsics) {
          if (intrinsics->size() != 4) throw py::value_error("intrinsics: expected (fx, fy, cx, cy) in pixels");
          CameraIntrinsics camera;
          camera.fx = (*intrinsics)[0];
          camera.fy = (*intrinsics)[1];
          camera.cx = (*intrinsics)[2];
          camera.cy = (*intrinsics)[3];
          params.depth_camera.intrinsics = camera;
        }
        if (depth_scale) params.depth_camera.depth_scale = *depth_scale;
        ProgressCallback callback;
        if (!progress.is_none())
          callback = [progress](const std::string& stage, std::size_t done, std::size_t total) {
            py::gil_scoped_acquire acquire;  // called from worker threads
            progress(stage, done, total);
          };
        reconstruction::ReconstructionResult r;
        {
          py::gil_scoped_release release;
          r = reconstruction::reconstructRawlog(input, params, callback);
        }
        py::dict report;
        report["scans"] = r.poses.size();
        report["pose_matching"] = r.pose_matching;
        report["scan_spacing_m"] = r.scan_spacing_m;
        report["raw_mesh"] = meshingReport(r.raw_meshing);
        report["filtered_mesh"] = meshingReport(r.filtered_meshing);
        report["time_ms"] = r.times.total_ms;
        py::dict out;
        out["cloud"] = std::move(r.cloud);
        out["raw_mesh"] = std::move(r.raw_mesh);
        out["filtered_mesh"] = std::move(r.filtered_mesh);
        out["poses"] = posesArray(r.poses);
        out["reported_poses"] = posesArray(r.reported_poses);
        out["report"] = report;
        return out;
      },
      py::arg("input"), py::arg("poses") = "", py::arg("intrinsics") = py::none(), py::arg("depth_scale") = py::none(),
      py::arg("progress") = py::none(),
      "The reconstruction pipeline of `icrkit reconstruct` on an MRPT rawlog or a TUM RGB-D folder: registration, "
      "fusion, raw and filtered meshes. `poses`: a TUM pose file (a folder's reported poses); `intrinsics`: "
      "(fx, fy, cx, cy) pixels; `depth_scale`: depth counts per metre; `progress(stage, done, total)` is called "
      "from worker threads (with the GIL). Returns a dict: cloud (PointCloud), raw_mesh, filtered_mesh "
      "(TriangleMesh), poses and reported_poses ((K, 4, 4) sensor poses, MRPT axes), report (counts, loops, "
      "components, time). docs/reconstruction.md.");

  m.def(
      "smooth",
      [](const py::handle& points, const py::handle& normals, std::optional<double> radius, double radius_factor,
         int passes, const std::string& preselection, std::optional<std::vector<double>> viewpoint,
         double window_normal_angle) {
        PointCloud cloud = asCloud(points, normals);
        ndt::SmoothingParameters params;
        params.radius = radius ? Length::metres(*radius) : Length::spacings(radius_factor);
        params.passes = passes;
        params.max_normal_angle = window_normal_angle;
        params.preselection.rule = ndt::parsePreselectionRule(preselection, "preselection");
        if (viewpoint) {
          if (viewpoint->size() != 3) throw py::value_error("viewpoint: expected (x, y, z)");
          params.viewpoint = Eigen::Vector3d((*viewpoint)[0], (*viewpoint)[1], (*viewpoint)[2]);
        }
        // A fused cloud knows each point's sensor: its normals face it.
        if (!params.viewpoint) params.viewpoints = reconstruction::fusionViewpoints(cloud);
        {
          py::gil_scoped_release release;
          ndt::smoothPointCloud(cloud, params);
        }
        return cloud;
      },
      py::arg("points"), py::arg("normals") = py::none(), py::arg("radius") = py::none(),
      py::arg("radius_factor") = 4.0, py::arg("passes") = 1, py::arg("preselection") = "default",
      py::arg("viewpoint") = py::none(), py::arg("window_normal_angle") = M_PI,
      "The 3D-NDT smoothing layer (Krug et al., Algorithm 1) and preselection. `points`: (N, 3) float64 metres or a "
      "PointCloud. `radius` in metres (None: radius_factor x the median spacing). `window_normal_angle` (radians, "
      "needs normals): windows keep only points whose normal is within it of their centre's (one-sided windows for "
      "thin walls; pi: the paper's window). Without `viewpoint`, a fused cloud's normals face each point's own "
      "sensor (its viewpoint_x/y/z attributes). Returns a new PointCloud with the "
      "smoothed points, v3 normals and the attributes cardinality, flatness, displacement (m), normal_sigma (rad), "
      "position_sigma (m) and excluded (unless preselection='none'). docs/smoothing.md.");

  m.def(
      "ball_pivoting",
      [](const py::handle& points, const py::handle& normals, std::optional<std::vector<double>> radii) {
        PointCloud cloud = asCloud(points, normals);
        if (!cloud.hasNormals()) throw py::value_error("normals: ball pivoting needs one unit normal per point");
        reconstruction::BallPivotingParameters params;
        if (radii) {
          params.radii.clear();
          for (double r : *radii) params.radii.push_back(Length::metres(r));
        }
        py::gil_scoped_release release;
        return reconstruction::ballPivoting(cloud, params).mesh;
      },
      py::arg("points"), py::arg("normals") = py::none(), py::arg("radii") = py::none(),
      "Ball pivoting (Bernardini et al. 1999) with hole filling and the thinned points put back. `radii` in metres "
      "(None: 1.5 and 2.5 x the median spacing). Returns a TriangleMesh whose vertices are the input points, with "
      "their attributes. docs/meshing.md.");

  m.def(
      "independent_contact_regions",
      [](const TriangleMesh& mesh, const std::vector<int>& contacts, const std::string& model, double mu, int edges,
         double mu_t, double alpha, std::optional<double> tws_radius, const std::string& mode,
         const std::string& torque_reference, const py::handle& excluded, std::optional<double> conservative,
         std::optional<double> normal_uncertainty, std::optional<double> position_uncertainty,
         std::optional<double> patch_radius) {
        icr::IcrParameters params;
        params.contact_model = contactModel(model, mu, edges, mu_t);
        params.alpha = alpha;
        if (tws_radius) params.tws_radius = *tws_radius;
        if (mode != "bfs" && mode != "full") throw InputError("mode", "", "expected bfs or full, got '" + mode + "'");
        params.mode = mode == "full" ? icr::GrowthMode::Full : icr::GrowthMode::BreadthFirst;
        if (conservative || normal_uncertainty || position_uncertainty) {
          params.conservative = icr::ConservativeGrowth{};
          if (conservative) params.conservative->sigmas = *conservative;
          params.conservative->normal_angle = normal_uncertainty;
          params.conservative->position_offset = position_uncertainty;
        }
        std::vector<std::uint8_t> mask = exclusionMask(mesh, excluded);
        const icr::TorqueReference reference = icr::parseTorqueReference(torque_reference);
        py::gil_scoped_release release;
        const icr::GraspableObject object = icr::GraspableObject::withDefaultFrame(mesh, std::move(mask), reference);
        icr::IcrResult result;
        if (patch_radius) {
          icr::PatchParameters patch;
          patch.radius_m = *patch_radius;
          const icr::ContactPatches patches(object, patch);
          result = icr::computePatchContactRegions(object, patches, contacts, params);
        } else {
          result = icr::computeIndependentContactRegions(object, contacts, params);
        }
        py::gil_scoped_acquire acquire;
        return resultToDict(result);
      },
      py::arg("mesh"), py::arg("contacts"), py::arg("model") = "frictional", py::arg("mu") = 0.8,
      py::arg("edges") = 8, py::arg("mu_t") = 0.5, py::arg("alpha") = 0.5, py::arg("tws_radius") = py::none(),
      py::arg("mode") = "bfs", py::arg("torque_reference") = "origin", py::arg("excluded") = py::none(),
      py::arg("conservative") = py::none(), py::arg("normal_uncertainty") = py::none(),
      py::arg("position_uncertainty") = py::none(), py::arg("patch_radius") = py::none(),
      "Independent Contact Regions (Krug et al. 2010) of a force-closure prototype grasp given by vertex indices. "
      "TWS: a ball of alpha x epsilon (or `tws_radius`). `excluded`: one flag per vertex (None: the mesh's "
      "`excluded` attribute). `conservative`: K, uncertainty-aware growth from the normal_sigma / position_sigma "
      "attributes, or fixed `normal_uncertainty` (rad) and `position_uncertainty` (m). `patch_radius` (m): the "
      "authors' multi-point contacts. Returns a dict: epsilon, lambda_m, tws_radius, gws_facets, regions (finger, "
      "contact, vertices, area_m2, recommended), vertices_tested, time_ms. The same numbers as `icrkit icr`.");

  m.def(
      "plan",
      [](const TriangleMesh& mesh, std::vector<std::size_t> fingers, std::size_t top, std::size_t candidates,
         std::optional<double> tws_radius, double alpha, const std::string& model, double mu, int edges, double mu_t,
         double placement_error, double task_margin, std::uint64_t seed, const std::string& torque_reference,
         const py::handle& excluded, const std::string& mesh_path, std::optional<double> patch_radius) {
        planning::PlanningParameters params;
        if (patch_radius) {
          params.patch = icr::PatchParameters{};
          params.patch->radius_m = *patch_radius;
        }
        params.finger_counts = std::move(fingers);
        params.top = top;
        params.candidates = candidates;
        params.regions.contact_model = contactModel(model, mu, edges, mu_t);
        params.regions.alpha = alpha;
        params.regions.tws_radius = tws_radius;
        params.placement.placement_error_m = placement_error;
        params.task_margin = task_margin;
        params.seed = seed;
        std::vector<std::uint8_t> mask = exclusionMask(mesh, excluded);
        const icr::TorqueReference reference = icr::parseTorqueReference(torque_reference);
        std::string text;
        {
          py::gil_scoped_release release;
          const icr::GraspableObject object = icr::GraspableObject::withDefaultFrame(mesh, std::move(mask), reference);
          text = planning::planJson(mesh_path, object, params.regions.contact_model, planning::planGrasps(object, params));
        }
        return py::module_::import("json").attr("loads")(text);
      },
      py::arg("mesh"), py::arg("fingers") = std::vector<std::size_t>{4}, py::arg("top") = 10,
      py::arg("candidates") = 1000, py::arg("tws_radius") = py::none(), py::arg("alpha") = 0.5,
      py::arg("model") = "frictional", py::arg("mu") = 0.8, py::arg("edges") = 8, py::arg("mu_t") = 0.5,
      py::arg("placement_error") = 0.003, py::arg("task_margin") = 0.25, py::arg("seed") = 1,
      py::arg("torque_reference") = "centroid", py::arg("excluded") = py::none(), py::arg("mesh_path") = "",
      py::arg("patch_radius") = py::none(),
      "Grasps a robot can execute on `mesh` (`icrkit plan`, docs/planning.md): returns the plan as the dict "
      "plan.json holds (grasps best first, each with its regions and recommended contacts); `mesh_path` is "
      "recorded as its \"mesh\". `patch_radius` (metres): fingers as patches (`--patch-radius`).");

  m.def(
      "sample_grasps",
      [](const TriangleMesh& mesh, std::size_t fingers, std::size_t count, std::uint64_t seed, double min_epsilon,
         const std::string& model, double mu, int edges, double mu_t, const std::string& torque_reference,
         const py::handle& excluded) {
        const icr::ContactModel contact = contactModel(model, mu, edges, mu_t);
        std::vector<std::uint8_t> mask = exclusionMask(mesh, excluded);
        const icr::TorqueReference reference = icr::parseTorqueReference(torque_reference);
        icr::GraspSamplingParameters params;
        params.fingers = fingers;
        params.count = count;
        params.seed = seed;
        params.min_epsilon = min_epsilon;
        std::vector<icr::SampledGrasp> grasps;
        {
          py::gil_scoped_release release;
          const icr::GraspableObject object = icr::GraspableObject::withDefaultFrame(mesh, std::move(mask), reference);
          grasps = icr::sampleForceClosureGrasps(object, contact, params);
        }
        py::list out;
        for (const icr::SampledGrasp& g : grasps)
          out.append(py::dict(py::arg("contacts") = g.contacts, py::arg("epsilon") = g.epsilon));
        return out;
      },
      py::arg("mesh"), py::arg("fingers") = 4, py::arg("count") = 200, py::arg("seed") = 1,
      py::arg("min_epsilon") = 0.0, py::arg("model") = "frictional", py::arg("mu") = 0.8, py::arg("edges") = 8,
      py::arg("mu_t") = 0.5, py::arg("torque_reference") = "origin", py::arg("excluded") = py::none(),
      "Random force-closure grasps (deterministic for a seed, whatever the thread count), as `icrkit grasps`: a list "
      "of dicts {contacts, epsilon}.");
}

}  // namespace icrkit::python
