// A reconstruction fed from memory, as a camera driver would feed it: depth
// images of a 6 cm ball on a table, rendered here (ray casting), handed one
// by one with their camera poses to a Reconstructor; then the meshes.
// Exits non-zero when the result is not the ball.

#include <icrkit/reconstruction/input/depth_image_scan.hpp>
#include <icrkit/reconstruction/reconstructor.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

namespace {

constexpr double kRadius = 0.03;                                    // metres
const Eigen::Vector3d kCentre(0.0, 0.0, kRadius);                   // resting on the table z = 0
constexpr int kWidth = 320, kHeight = 240;

// Camera-to-object pose, optical axes (x right, y down, z forward), looking
// at the ball from `azimuth`, 40 cm away and 30 cm up.
Eigen::Isometry3d cameraPose(double azimuth) {
  const Eigen::Vector3d eye(0.4 * std::cos(azimuth), 0.4 * std::sin(azimuth), 0.3);
  const Eigen::Vector3d forward = (kCentre - eye).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear().col(0) = right;
  pose.linear().col(1) = down;
  pose.linear().col(2) = forward;
  pose.translation() = eye;
  return pose;
}

// What a 16-bit depth camera (millimetres) sees of the ball and the table.
std::vector<std::uint16_t> render(const Eigen::Isometry3d& pose, const icrkit::CameraIntrinsics& k) {
  std::vector<std::uint16_t> depth(static_cast<std::size_t>(kWidth) * kHeight, 0);
  const Eigen::Vector3d eye = pose.translation();
  for (int r = 0; r < kHeight; ++r)
    for (int c = 0; c < kWidth; ++c) {
      const Eigen::Vector3d ray_camera((c - k.cx) / k.fx, (r - k.cy) / k.fy, 1.0);  // z = 1: depth units
      const Eigen::Vector3d ray = pose.linear() * ray_camera;
      double t = -1.0;
      const Eigen::Vector3d oc = eye - kCentre;
      const double b = oc.dot(ray), a = ray.squaredNorm(), q = oc.squaredNorm() - kRadius * kRadius;
      const double disc = b * b - a * q;
      if (disc >= 0) t = (-b - std::sqrt(disc)) / a;
      if (t <= 0 && ray.z() < 0) t = -eye.z() / ray.z();  // the table
      if (t > 0) depth[static_cast<std::size_t>(r) * kWidth + c] = static_cast<std::uint16_t>(std::lround(t * 1000.0));
    }
  return depth;
}

}  // namespace

int main() {
  using namespace icrkit::reconstruction;
  icrkit::CameraIntrinsics k;
  k.width = kWidth;
  k.height = kHeight;
  k.fx = k.fy = 300.0;
  k.cx = 159.5;
  k.cy = 119.5;

  ReconstructionParameters params;
  params.register_scans = false;  // the poses here are exact
  params.auto_crop_half_size = 0.06;
  Reconstructor reconstructor(params);
  for (int view = 0; view < 12; ++view) {
    const Eigen::Isometry3d camera = cameraPose(2.0 * M_PI * view / 12.0);
    const std::vector<std::uint16_t> depth = render(camera, k);  // the driver's buffer
    DepthImageView image;
    image.width = kWidth;
    image.height = kHeight;
    image.counts = depth.data();
    image.depth_scale = 1000.0;
    DepthImageMeta meta;
    meta.intrinsics = k;
    meta.sensor_pose = opticalToSensorPose(camera);
    meta.timestamp = 0.1 * view;
    reconstructor.addDepthImage(image, meta);
  }
  const ReconstructionResult& result = reconstructor.update();

  double worst = 0.0;
  for (const Eigen::Vector3d& p : result.filtered_mesh.vertices.positions)
    worst = std::max(worst, std::abs((p - kCentre).norm() - kRadius));
  std::printf("%zu scans, %zu fused points, filtered mesh %zu faces, worst vertex %.2f mm off the ball\n",
              reconstructor.scanCount(), result.cloud.positions.size(), result.filtered_mesh.faces.size(), worst * 1e3);
  const bool ok = result.filtered_mesh.faces.size() > 1000 && worst < 0.003 && result.raw_mesh.faces.size() > 1000;
  if (!ok) std::fprintf(stderr, "reconstruct_from_memory: FAILED: the meshes are not the ball\n");
  return ok ? 0 : 1;
}
