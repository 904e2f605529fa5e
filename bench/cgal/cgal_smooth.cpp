// The anchor of issue 34 (docs/smoothing.md): CGAL's edge-aware bilateral
// smoothing and jet smoothing of an oriented point cloud, for side-by-side
// runs against icrkit's 3D-NDT smoothing on the same fused clouds. A
// benchmark tool only (Debian's libcgal-dev), never linked into icrkit.
//
//   cgal_smooth IN.ply OUT.ply bilateral|jet K [ITERATIONS [SHARPNESS_DEG]]
// Prints one JSON line: {"method", "k", "iterations", "points", "time_ms"}.

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/point_cloud.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/bilateral_smooth_point_set.h>
#include <CGAL/jet_smooth_point_set.h>
#include <CGAL/property_map.h>

#include <chrono>
#include <cstdio>
#include <exception>
#include <string>
#include <utility>
#include <vector>

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using PointWithNormal = std::pair<Point, Vector>;

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: %s IN.ply OUT.ply bilateral|jet K [ITERATIONS [SHARPNESS_DEG]]\n", argv[0]);
    return 2;
  }
  try {
    const std::string method = argv[3];
    const unsigned k = static_cast<unsigned>(std::stoul(argv[4]));
    const int iterations = argc > 5 ? std::stoi(argv[5]) : 1;
    const double sharpness = argc > 6 ? std::stod(argv[6]) : 25.0;
    if (method != "bilateral" && method != "jet") throw std::invalid_argument("method must be bilateral or jet");
    icrkit::PointCloud cloud = icrkit::io::readPointCloud(argv[1]);
    if (method == "bilateral" && !cloud.hasNormals()) throw std::invalid_argument(std::string(argv[1]) + ": bilateral smoothing needs normals");
    std::vector<PointWithNormal> points;
    points.reserve(cloud.size());
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const auto& p = cloud.positions[i];
      const Eigen::Vector3d n = cloud.hasNormals() ? cloud.normals[i] : Eigen::Vector3d::Zero();
      points.emplace_back(Point(p.x(), p.y(), p.z()), Vector(n.x(), n.y(), n.z()));
    }
    const auto start = std::chrono::steady_clock::now();
    const auto parameters = CGAL::parameters::point_map(CGAL::First_of_pair_property_map<PointWithNormal>())
                                .normal_map(CGAL::Second_of_pair_property_map<PointWithNormal>());
    for (int it = 0; it < iterations; ++it) {
      if (method == "bilateral")
        CGAL::bilateral_smooth_point_set<CGAL::Parallel_if_available_tag>(points, k, parameters.sharpness_angle(sharpness));
      else
        CGAL::jet_smooth_point_set<CGAL::Parallel_if_available_tag>(points, k, parameters);
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const Point& p = points[i].first;
      cloud.positions[i] = Eigen::Vector3d(p.x(), p.y(), p.z());
      if (method == "bilateral") {
        const Vector& n = points[i].second;
        cloud.normals[i] = Eigen::Vector3d(n.x(), n.y(), n.z());
      }
    }
    icrkit::io::writePointCloud(argv[2], cloud);
    std::printf("{\"method\": \"%s\", \"k\": %u, \"iterations\": %d, \"points\": %zu, \"time_ms\": %.1f}\n", method.c_str(), k,
                iterations, cloud.size(), ms);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cgal_smooth: %s\n", e.what());
    return 2;
  }
}
