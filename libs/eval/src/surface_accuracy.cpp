#include <icrkit/eval/surface_accuracy.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/mesh_topology.hpp>
#include <icrkit/core/ray_caster.hpp>

#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <iomanip>
#include <sstream>
#include <map>
#include <utility>
#include <vector>

namespace icrkit::eval {
namespace {

// Unit face normals of the reference, turned to agree with its vertex
// normals where it has them (a CAD file's winding may be either way).
std::vector<Eigen::Vector3d> orientedFaceNormals(const TriangleMesh& reference) {
  const auto& p = reference.vertices.positions;
  const bool with_normals = reference.vertices.normals.size() == reference.vertexCount();
  std::vector<Eigen::Vector3d> normals(reference.faces.size(), Eigen::Vector3d::Zero());
  for (std::size_t f = 0; f < reference.faces.size(); ++f) {
    const Triangle& t = reference.faces[f];
    Eigen::Vector3d n = (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]);
    const double length = n.norm();
    if (!(length > 0.0)) continue;
    n /= length;
    if (with_normals) {
      const Eigen::Vector3d v = reference.vertices.normals[t[0]] + reference.vertices.normals[t[1]] +
                                reference.vertices.normals[t[2]];
      if (v.dot(n) < 0.0) n = -n;
    }
    normals[f] = n;
  }
  return normals;
}

// Points along the reference's sharp edges, spaced at most `step` apart: the
// distance to the nearest such point is the distance to the sharp edges to
// within step / 2.
std::vector<Eigen::Vector3d> sharpEdgeSamples(const TriangleMesh& reference, const std::vector<Eigen::Vector3d>& normals,
                                              double crease_angle, double step, std::size_t& sharp_edges) {
  std::map<std::pair<int, int>, std::vector<std::size_t>> edge_faces;
  for (std::size_t f = 0; f < reference.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = reference.faces[f][k], b = reference.faces[f][(k + 1) % 3];
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(f);
    }
  const double min_cos = std::cos(crease_angle);
  std::vector<Eigen::Vector3d> samples;
  sharp_edges = 0;
  for (const auto& [edge, faces] : edge_faces) {
    if (faces.size() != 2) continue;  // a border or a non-manifold edge is no crease
    const Eigen::Vector3d& n0 = normals[faces[0]];
    const Eigen::Vector3d& n1 = normals[faces[1]];
    if (n0.isZero() || n1.isZero() || n0.dot(n1) >= min_cos) continue;
    ++sharp_edges;
    const Eigen::Vector3d& a = reference.vertices.positions[static_cast<std::size_t>(edge.first)];
    const Eigen::Vector3d& b = reference.vertices.positions[static_cast<std::size_t>(edge.second)];
    const int pieces = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step)));
    for (int i = 0; i <= pieces; ++i) samples.push_back(a + (b - a) * (static_cast<double>(i) / pieces));
  }
  return samples;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<long>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  double m = *mid;
  if (v.size() % 2 == 0) m = 0.5 * (m + *std::max_element(v.begin(), mid));
  return m;
}

double percentile90(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto at = v.begin() + static_cast<long>(std::min(v.size() - 1, (v.size() * 9) / 10));
  std::nth_element(v.begin(), at, v.end());
  return *at;
}

SurfaceAccuracyGroup summarize(const std::vector<double>& distances, const std::vector<double>& angles) {
  SurfaceAccuracyGroup g;
  g.vertices = distances.size();
  if (distances.empty()) return g;
  double sum = 0.0;
  for (double d : distances) sum += d;
  g.mean_distance_m = sum / static_cast<double>(distances.size());
  g.median_distance_m = median(distances);
  g.median_normal_error_rad = median(angles);
  g.p90_normal_error_rad = percentile90(angles);
  return g;
}

}  // namespace

void SurfaceAccuracyParameters::validate() const {
  if (!(std::isfinite(crease_angle_rad) && crease_angle_rad > 0.0 && crease_angle_rad < M_PI))
    throw InputError("SurfaceAccuracyParameters::crease_angle_rad", "",
                     "expected an angle in (0, pi) radians, got " + std::to_string(crease_angle_rad));
  if (!(std::isfinite(max_line_distance_m) && max_line_distance_m >= 0.0))
    throw InputError("SurfaceAccuracyParameters::max_line_distance_m", "",
                     "expected a finite distance >= 0 (metres), got " + std::to_string(max_line_distance_m));
  if (!(std::isfinite(edge_distance_m) && edge_distance_m >= 0.0))
    throw InputError("SurfaceAccuracyParameters::edge_distance_m", "",
                     "expected a finite distance >= 0 (metres), got " + std::to_string(edge_distance_m));
}

SurfaceAccuracy measureSurfaceAccuracy(const TriangleMesh& mesh, const TriangleMesh& reference,
                                       const SurfaceAccuracyParameters& params) {
  params.validate();
  if (reference.faces.empty()) throw InputError("reference mesh", "", "has no faces");
  SurfaceAccuracy result;
  const std::vector<Eigen::Vector3d> face_normals = orientedFaceNormals(reference);
  // Samples 0.5 mm apart (at most half the edge distance) find the edges
  // to within 0.25 mm.
  const double step = std::max(1e-4, std::min(5e-4, 0.5 * params.edge_distance_m));
  const std::vector<Eigen::Vector3d> edge_samples =
      sharpEdgeSamples(reference, face_normals, params.crease_angle_rad, step, result.sharp_edges);
  std::unique_ptr<KdTree> edges;
  if (!edge_samples.empty()) edges = std::make_unique<KdTree>(edge_samples);

  const std::vector<std::uint8_t> used = referencedVertices(mesh);
  std::vector<Eigen::Vector3d> queries;
  std::vector<std::size_t> ids;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
    if (used[v]) {
      queries.push_back(mesh.vertices.positions[v]);
      ids.push_back(v);
    }
  const RayCaster caster(reference);
  const std::vector<ClosestPoint> nearest = caster.closestPoints(queries);
  std::vector<int> touched(ids.size(), -1);  // the reference face whose normal is compared
  result.normals = mesh.vertices.normals.size() == mesh.vertexCount();
  // Where the vertex has a normal, "there" is where a finger approaching
  // along it touches the reference: the nearest crossing of the normal's
  // line with a reference face turned its way (within max_line_distance_m),
  // as eq. (3) maps by touch. The nearest reference point alone is often on
  // a thin wall's other side (a cup's inner surface), whose normal is
  // opposite.
  if (result.normals) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ids.size(), 256), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const Eigen::Vector3d& n = mesh.vertices.normals[ids[i]];
        const double length = n.norm();
        if (!(length > 0.0)) continue;
        const Eigen::Vector3d direction = n / length;
        double best = std::numeric_limits<double>::infinity();
        for (const RayHit& hit : caster.allHitsOnLine(queries[i], direction)) {
          const double t = std::abs(hit.distance);
          if (t > params.max_line_distance_m || t >= best) continue;
          if (!(face_normals[static_cast<std::size_t>(hit.face)].dot(direction) > 0.0)) continue;
          best = t;
          touched[i] = hit.face;
        }
      }
    });
  }

  std::vector<double> d_all, a_all, d_near, a_near, d_else, a_else;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const ClosestPoint& c = nearest[i];
    if (!c.found) continue;
    const double distance = c.distance;
    double angle = 0.0;
    if (result.normals) {
      const Eigen::Vector3d& n = mesh.vertices.normals[ids[i]];
      const Eigen::Vector3d& r = face_normals[static_cast<std::size_t>(touched[i] >= 0 ? touched[i] : c.face)];
      const double length = n.norm();
      angle = length > 0.0 && !r.isZero() ? std::acos(std::clamp(n.dot(r) / length, -1.0, 1.0)) : M_PI;
    }
    const bool near_edge = edges && edges->nearestWithin(c.point, params.edge_distance_m) >= 0;
    d_all.push_back(distance);
    a_all.push_back(angle);
    (near_edge ? d_near : d_else).push_back(distance);
    (near_edge ? a_near : a_else).push_back(angle);
  }
  result.all = summarize(d_all, a_all);
  result.near_edges = summarize(d_near, a_near);
  result.elsewhere = summarize(d_else, a_else);
  return result;
}

std::string surfaceAccuracyJson(const SurfaceAccuracy& accuracy) {
  const auto group = [&](const SurfaceAccuracyGroup& g) {
    nlohmann::json j{{"vertices", g.vertices},
                     {"mean_distance_m", g.mean_distance_m},
                     {"median_distance_m", g.median_distance_m}};
    if (accuracy.normals) {
      j["median_normal_error_deg"] = g.median_normal_error_rad * 180.0 / M_PI;
      j["p90_normal_error_deg"] = g.p90_normal_error_rad * 180.0 / M_PI;
    }
    return j;
  };
  const nlohmann::json j{{"all", group(accuracy.all)},
                         {"near_edges", group(accuracy.near_edges)},
                         {"elsewhere", group(accuracy.elsewhere)},
                         {"sharp_edges", accuracy.sharp_edges}};
  return j.dump();
}

std::string datasetSurfaceAccuracyJson(const std::string& dataset, const TriangleMesh& cad, const TriangleMesh& raw,
                                       const TriangleMesh& filtered, const SurfaceAccuracyParameters& params) {
  const nlohmann::json j{
      {"dataset", dataset},
      {"crease_angle_deg", params.crease_angle_rad * 180.0 / M_PI},
      {"edge_distance_m", params.edge_distance_m},
      {"raw", nlohmann::json::parse(surfaceAccuracyJson(measureSurfaceAccuracy(raw, cad, params)))},
      {"filtered", nlohmann::json::parse(surfaceAccuracyJson(measureSurfaceAccuracy(filtered, cad, params)))}};
  return j.dump();
}

std::string surfaceAccuracyMarkdown(const std::vector<std::string>& jsonl_lines) {
  std::ostringstream out;
  out << "| dataset | mesh | mean distance mm (near edges / elsewhere) | median normal error deg near edges | "
         "median normal error deg elsewhere | vertices near edges |\n|---|---|---|---:|---:|---:|\n";
  const auto fixed = [](double v, int digits) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(digits) << v;
    return s.str();
  };
  for (const std::string& line : jsonl_lines) {
    const nlohmann::json j = nlohmann::json::parse(line);
    for (const char* mesh : {"filtered", "raw"}) {
      const nlohmann::json& m = j.at(mesh);
      const auto angle = [&](const char* group) {
        const nlohmann::json& g = m.at(group);
        return g.contains("median_normal_error_deg") && g.at("vertices").get<std::size_t>() > 0
                   ? fixed(g.at("median_normal_error_deg").get<double>(), 1)
                   : std::string("–");
      };
      out << "| " << j.at("dataset").get<std::string>() << " | " << mesh << " | "
          << fixed(1e3 * m.at("all").at("mean_distance_m").get<double>(), 2) << " ("
          << fixed(1e3 * m.at("near_edges").at("mean_distance_m").get<double>(), 2) << " / "
          << fixed(1e3 * m.at("elsewhere").at("mean_distance_m").get<double>(), 2) << ") | " << angle("near_edges")
          << " | " << angle("elsewhere") << " | " << m.at("near_edges").at("vertices").get<std::size_t>() << " of "
          << m.at("all").at("vertices").get<std::size_t>() << " |\n";
    }
  }
  return out.str();
}

}  // namespace icrkit::eval
