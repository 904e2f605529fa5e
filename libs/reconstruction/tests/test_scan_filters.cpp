/// \file
/// Scan filters on synthetic range images with known answers.

#include "simulated_recordings.hpp"
#include "synthetic_scans.hpp"

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/ray_caster.hpp>

#include <icrkit/reconstruction/input/scan_filters.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace icrkit::reconstruction {
namespace {

using testing_support::blankScan;
using testing_support::castRays;
using testing_support::lookAt;
using testing_support::unprojectPinhole;

RangeScan frontalScan() {
  return blankScan(80, 60, 80.0, lookAt(Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d(0, 0, 0)));
}

TEST(JumpEdges, StepEdgeFlyingPixelsAreRemoved) {
  RangeScan scan = frontalScan();
  for (int r = 0; r < 60; ++r)
    for (int c = 0; c < 80; ++c) {
      float depth = c < 40 ? 0.5f : 1.0f;
      if (c == 40) depth = 0.62f;  // mixed pixels between the two surfaces
      if (c == 41) depth = 0.81f;
      scan.range[r * 80 + c] = depth;
    }
  unprojectPinhole(scan);
  const FilterReport report = filterJumpEdges(scan, {});
  EXPECT_EQ(report.pixels_before, 4800u);
  EXPECT_EQ(report.removed + scan.validPixels(), 4800u);
  EXPECT_EQ(scan.points.size(), scan.validPixels());
  for (int r = 0; r < 60; ++r) {
    EXPECT_EQ(scan.range[r * 80 + 40], 0.0f) << "row " << r;
    EXPECT_EQ(scan.range[r * 80 + 41], 0.0f) << "row " << r;
    for (int c = 0; c < 80; ++c)
      if (c < 39 || c > 42) {
        EXPECT_GT(scan.range[r * 80 + c], 0.0f) << r << "," << c;
      }
  }
  // The two mixed columns plus at most the edge pixel on each side.
  EXPECT_LE(report.removed, 4u * 60u);
  EXPECT_GE(report.removed, 2u * 60u);
}

TEST(JumpEdges, SmoothSurfacesStay) {
  // A plane at 45 degrees to the line of sight is well measured: nothing goes.
  RangeScan scan = frontalScan();
  castRays(scan, [](const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
    const Eigen::Vector3d n = Eigen::Vector3d(-1, 1, 0).normalized();  // plane through the origin
    const double denom = n.dot(d);
    return std::abs(denom) < 1e-9 ? -1.0 : -n.dot(o) / denom;
  });
  ASSERT_EQ(scan.validPixels(), 4800u);
  EXPECT_EQ(filterJumpEdges(scan, {}).removed, 0u);
}

// A 20 x 20 pixel square at 0.5 m in front of a wall at 1 m, a 30 x 10
// pixel gap without returns in the wall, and one dropout inside the square.
TEST(ForegroundEdges, ErodesEdgesInFrontOfBackgroundAndGaps) {
  RangeScan scan = frontalScan();
  auto at = [](int r, int c) { return static_cast<std::size_t>(r) * 80 + c; };
  for (int r = 0; r < 60; ++r)
    for (int c = 0; c < 80; ++c) scan.range[at(r, c)] = (r >= 10 && r < 30 && c >= 10 && c < 30) ? 0.5f : 1.0f;
  for (int r = 40; r < 50; ++r)
    for (int c = 40; c < 70; ++c) scan.range[at(r, c)] = 0.0f;  // the gap
  scan.range[at(20, 20)] = 0.0f;                                 // the dropout
  unprojectPinhole(scan);
  const std::size_t before = scan.validPixels();
  ForegroundEdgeParameters params;
  params.pixels = 1;
  const FilterReport report = filterForegroundEdges(scan, params);
  EXPECT_EQ(report.pixels_before, before);
  EXPECT_EQ(scan.points.size(), scan.validPixels());
  // The square loses its outer ring (76 pixels), the wall its ring around
  // the gap (2 x 32 + 2 x 10 = 84), the dropout's neighbours nothing.
  EXPECT_EQ(report.removed, 76u + 84u);
  EXPECT_EQ(scan.range[at(10, 10)], 0.0f);
  EXPECT_EQ(scan.range[at(29, 15)], 0.0f);
  EXPECT_GT(scan.range[at(11, 11)], 0.0f);
  EXPECT_GT(scan.range[at(19, 20)], 0.0f);  // next to the dropout
  EXPECT_GT(scan.range[at(9, 10)], 0.0f);   // the wall behind the square's edge stays
  EXPECT_EQ(scan.range[at(39, 45)], 0.0f);
  EXPECT_GT(scan.range[at(38, 45)], 0.0f);
  // The image border is not an edge; 0 pixels is off.
  EXPECT_GT(scan.range[at(0, 0)], 0.0f);
  params.pixels = 0;
  EXPECT_EQ(filterForegroundEdges(scan, params).removed, 0u);
}

TEST(RangeGate, KeepsTheBand) {
  RangeScan scan = frontalScan();
  for (int c = 0; c < 80; ++c)
    for (int r = 0; r < 60; ++r) scan.range[r * 80 + c] = 0.2f + 0.02f * c;  // depth 0.2 .. 1.78
  unprojectPinhole(scan);
  RangeGateParameters params;
  params.min_range = 0.5;
  params.max_range = 1.0;
  const FilterReport report = filterRange(scan, params);
  for (std::size_t k = 0; k < scan.points.size(); ++k) {
    const double d = (scan.points[k] - scan.sensor_pose.translation()).norm();
    EXPECT_GE(d, 0.5);
    EXPECT_LE(d, 1.0);
  }
  EXPECT_EQ(report.removed + scan.points.size(), 4800u);
  EXPECT_GT(scan.points.size(), 1000u);
}

TEST(Confidence, ThresholdsConfidenceAndAmplitude) {
  RangeScan scan = frontalScan();
  std::fill(scan.range.begin(), scan.range.end(), 1.0f);
  unprojectPinhole(scan);
  scan.confidence = {80, 60, 1, std::vector<std::uint8_t>(4800, 255)};
  scan.intensity = {80, 60, 1, std::vector<std::uint8_t>(4800, 200)};
  scan.intensity_is_ir = true;
  for (int i = 0; i < 100; ++i) scan.confidence.data[i] = 10;
  for (int i = 50; i < 300; ++i) scan.intensity.data[i] = 5;
  ConfidenceFilterParameters params;
  params.min_confidence = 50;
  params.min_amplitude = 20;
  EXPECT_EQ(filterConfidence(scan, params).removed, 300u);
  EXPECT_EQ(scan.points.size(), 4500u);
  // Colour images are no amplitude.
  scan.intensity_is_ir = false;
  std::fill(scan.intensity.data.begin(), scan.intensity.data.end(), 0);
  EXPECT_EQ(filterConfidence(scan, params).removed, 0u);
}

// A 10 cm x 10 cm x 8 cm box standing on the plane z = 0.
double planeAndBox(const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double best = -1;
  if (d.z() < 0) {
    const double t = -o.z() / d.z();
    const Eigen::Vector3d p = o + t * d;
    if (std::abs(p.x()) < 0.4 && std::abs(p.y()) < 0.4) best = t;
  }
  const Eigen::Vector3d lo(-0.05, -0.05, 0.0), hi(0.05, 0.05, 0.08);
  double t0 = 0, t1 = 1e9;
  for (int a = 0; a < 3; ++a) {
    const double inv = 1.0 / d[a];
    double ta = (lo[a] - o[a]) * inv, tb = (hi[a] - o[a]) * inv;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (t0 <= t1 && t0 > 0 && (best < 0 || t0 < best)) best = t0;
  return best;
}

TEST(SupportPlane, PlaneAndBoxLosesItsPlane) {
  RangeScan scan = blankScan(160, 120, 150.0, lookAt(Eigen::Vector3d(0.45, 0.2, 0.35), Eigen::Vector3d(0, 0, 0.03)));
  castRays(scan, planeAndBox);
  const std::size_t all = scan.points.size();
  const Eigen::AlignedBox3d crop(Eigen::Vector3d(-0.15, -0.15, -0.02), Eigen::Vector3d(0.15, 0.15, 0.2));
  const FilterReport cropped = filterCropBox(scan, crop);
  EXPECT_GT(cropped.removed, 0u);
  EXPECT_EQ(scan.points.size(), all - cropped.removed);
  std::size_t box_points = 0;
  for (const auto& p : scan.points) box_points += p.z() > 1e-6;
  const PlaneRemovalReport report = removeSupportPlane(scan, crop, {});
  ASSERT_TRUE(report.found);
  EXPECT_NEAR(report.plane[2], 1.0, 1e-4);
  EXPECT_NEAR(report.plane[3], 0.0, 5e-4);
  std::size_t kept_box = 0;
  for (const auto& p : scan.points) {
    EXPECT_GT(p.z(), 0.003);  // nothing of the plane is left
    EXPECT_LE(std::abs(p.x()), 0.05 + 1e-5);
    EXPECT_LE(std::abs(p.y()), 0.05 + 1e-5);
    ++kept_box;
  }
  // The box loses only its bottom 4 mm (the inlier distance).
  EXPECT_GT(static_cast<double>(kept_box), 0.9 * static_cast<double>(box_points));
  EXPECT_GT(kept_box, 500u);

  // Deterministic: the same scan gives the same plane.
  RangeScan again = blankScan(160, 120, 150.0, scan.sensor_pose);
  castRays(again, planeAndBox);
  filterCropBox(again, crop);
  const PlaneRemovalReport report2 = removeSupportPlane(again, crop, {});
  EXPECT_EQ(report2.plane, report.plane);
  EXPECT_EQ(again.points, scan.points);
}

// The same scene in a frame whose +y is up (a model's frame, as the real
// recording's bun_zipper frame): with that up the table goes and the box
// stays; the filter must not look for the table along z.
TEST(SupportPlane, PlaneAlongTheGivenUp) {
  const Eigen::Isometry3d z_to_y(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()));
  const Eigen::Isometry3d to_z_up = z_to_y.inverse();
  RangeScan scan = blankScan(160, 120, 150.0,
                             z_to_y * lookAt(Eigen::Vector3d(0.45, 0.2, 0.35), Eigen::Vector3d(0, 0, 0.03)));
  castRays(scan, [&](const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
    return planeAndBox(to_z_up * o, to_z_up.linear() * d);
  });
  Eigen::AlignedBox3d crop;
  const Eigen::AlignedBox3d z_up_crop(Eigen::Vector3d(-0.15, -0.15, -0.02), Eigen::Vector3d(0.15, 0.15, 0.2));
  for (int c = 0; c < 8; ++c) crop.extend(z_to_y * z_up_crop.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));
  filterCropBox(scan, crop);
  std::size_t box_points = 0;
  for (const auto& p : scan.points) box_points += p.y() > 1e-6;
  PlaneRemovalParameters params;
  params.up = Eigen::Vector3d::UnitY();
  params.band = 0.5 * crop.sizes().y();
  const PlaneRemovalReport report = removeSupportPlane(scan, crop, params);
  ASSERT_TRUE(report.found);
  EXPECT_NEAR(report.plane[1], 1.0, 1e-4);
  EXPECT_NEAR(report.plane[3], 0.0, 5e-4);
  for (const auto& p : scan.points) EXPECT_GT(p.y(), 0.003);
  EXPECT_GT(static_cast<double>(scan.points.size()), 0.9 * static_cast<double>(box_points));
}

// The box alone (no table in view): its lowest 4 mm of sides fit a
// horizontal plane, but they face sideways, not up: nothing is removed.
// (Its top, were it inside the band, would face up: a known limit.)
TEST(SupportPlane, AnObjectOnNothingKeepsItsBottom) {
  RangeScan scan = blankScan(320, 240, 300.0, lookAt(Eigen::Vector3d(0.3, 0.15, 0.2), Eigen::Vector3d(0, 0, 0.03)));
  castRays(scan, [](const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
    const Eigen::Vector3d lo(-0.05, -0.05, 0.0), hi(0.05, 0.05, 0.08);
    double t0 = 0, t1 = 1e9;
    for (int a = 0; a < 3; ++a) {
      const double inv = 1.0 / d[a];
      double ta = (lo[a] - o[a]) * inv, tb = (hi[a] - o[a]) * inv;
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    return t0 <= t1 && t0 > 0 ? t0 : -1.0;
  });
  const Eigen::AlignedBox3d crop(Eigen::Vector3d(-0.15, -0.15, -0.02), Eigen::Vector3d(0.15, 0.15, 0.2));
  filterCropBox(scan, crop);
  std::size_t lowest = 0;
  for (const auto& p : scan.points) lowest += p.z() < 0.004;
  ASSERT_GT(lowest, 200u);  // enough for a plane of the old rule
  PlaneRemovalParameters params;
  params.band = 0.05;  // up to z = 0.03: the sides' lower part, not the top
  const std::size_t before = scan.points.size();
  const PlaneRemovalReport report = removeSupportPlane(scan, crop, params);
  EXPECT_FALSE(report.found);
  EXPECT_EQ(scan.points.size(), before);
}

TEST(SupportPlane, NoPlaneNoRemoval) {
  RangeScan scan = frontalScan();
  std::fill(scan.range.begin(), scan.range.end(), 1.0f);  // a wall: vertical, not a support
  unprojectPinhole(scan);
  const Eigen::AlignedBox3d crop(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1));
  const PlaneRemovalReport report = removeSupportPlane(scan, crop, {});
  EXPECT_FALSE(report.found);
  EXPECT_EQ(report.removed, 0u);
  EXPECT_EQ(scan.points.size(), 4800u);
}

}  // namespace
}  // namespace icrkit::reconstruction

namespace icrkit::reconstruction {
namespace {

// On a simulated Kinect recording (setup B: the cup on its support plate),
// crop box + support-plane removal leave the cup and little else.
TEST(SupportPlane, SimulatedRecordingKeepsOnlyTheObject) {
  const std::string dir = testing_support::simulatedRecording(4, true);
  const TriangleMesh object = io::readTriangleMesh(dir + "/object.ply");
  const RayCaster caster(object);
  Eigen::AlignedBox3d object_box;
  for (const auto& v : object.vertices.positions) object_box.extend(v);
  const Eigen::AlignedBox3d crop(object_box.min() - Eigen::Vector3d(0.03, 0.03, 0.03),
                                 object_box.max() + Eigen::Vector3d(0.03, 0.03, 0.01));
  for (RangeScan scan : readAllScans(dir + "/scans.rawlog")) {
    filterCropBox(scan, crop);
    std::size_t on_object_before = 0;
    for (const auto& p : scan.points) on_object_before += caster.closestPoint(p, 0.005).found;
    const PlaneRemovalReport report = removeSupportPlane(scan, crop, {});
    ASSERT_TRUE(report.found) << "scan " << scan.index;
    EXPECT_NEAR(report.plane[2], 1.0, 0.01);
    EXPECT_NEAR(report.plane[3], 0.0, 0.003);  // the plate's top is z = 0
    std::size_t on_object = 0;
    for (const auto& p : scan.points) on_object += caster.closestPoint(p, 0.005).found;
    EXPECT_GT(static_cast<double>(on_object), 0.98 * static_cast<double>(scan.points.size())) << "scan " << scan.index;
    // What goes of the object is its bottom rim within inlier_distance of the plate.
    EXPECT_GT(static_cast<double>(on_object), 0.9 * static_cast<double>(on_object_before)) << "scan " << scan.index;

    // The jump-edge filter takes the seams (silhouette, rim over the inside,
    // grazing sides of the cylinder), not the surface.
    const FilterReport edges = filterJumpEdges(scan, {});
    EXPECT_LT(static_cast<double>(edges.removed), 0.2 * static_cast<double>(edges.pixels_before));
  }
}

}  // namespace
}  // namespace icrkit::reconstruction
