#include <icrkit/reconstruction/calibration/board_lattice_pose.hpp>

#include <icrkit/core/error.hpp>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <vector>

namespace icrkit::reconstruction {
namespace {

cv::Mat greyOf(const Image8& image) {
  cv::Mat grey(image.height, image.width, CV_8UC1);
  for (int i = 0; i < image.width * image.height; ++i) {
    const std::uint8_t* p = &image.data[static_cast<std::size_t>(i) * image.channels];
    grey.data[i] = image.channels == 3 ? static_cast<std::uint8_t>((299 * p[0] + 587 * p[1] + 114 * p[2]) / 1000) : p[0];
  }
  return grey;
}

// World (object frame) -> optical frame of the camera at an MRPT sensor pose.
Eigen::Isometry3d opticalFromWorld(const Eigen::Isometry3d& sensor_pose) {
  const Eigen::Matrix3d m = mrptSensorAxesInOptical();
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = m * sensor_pose.linear().transpose();
  t.translation() = -t.linear() * sensor_pose.translation();
  return t;
}

Eigen::Isometry3d sensorPoseFromOptical(const Eigen::Isometry3d& optical_from_world) {
  const Eigen::Matrix3d m = mrptSensorAxesInOptical();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = optical_from_world.linear().transpose() * m;
  pose.translation() = -optical_from_world.linear().transpose() * optical_from_world.translation();
  return pose;
}

double sample(const cv::Mat& grey, const cv::Point2f& p) {
  const int x = static_cast<int>(std::lround(p.x)), y = static_cast<int>(std::lround(p.y));
  if (x < 0 || y < 0 || x >= grey.cols || y >= grey.rows) return -1.0;
  return grey.at<std::uint8_t>(y, x);
}

}  // namespace

LatticePose latticeCameraPose(const RangeScan& scan, const BoardLattice& lattice, const LatticePoseParameters& params) {
  if (!(lattice.square_size > 0.0) || std::abs(lattice.x_axis.norm() - 1.0) > 1e-6 ||
      std::abs(lattice.y_axis.norm() - 1.0) > 1e-6 || std::abs(lattice.x_axis.dot(lattice.y_axis)) > 1e-6)
    throw InputError("board lattice", "", "expected a square size > 0 and orthonormal x and y axes");
  LatticePose result;
  const Image8& image = scan.intensity;
  if (image.empty() || (image.channels != 1 && image.channels != 3)) return result;
  const CameraIntrinsics& cam = scan.camera_intensity.fx > 0 ? scan.camera_intensity : scan.camera;
  const cv::Mat grey = greyOf(image);
  const cv::Mat k = (cv::Mat_<double>(3, 3) << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
  const cv::Mat d(1, 5, CV_64F, const_cast<double*>(cam.distortion.data()));
  const Eigen::Vector3d normal = lattice.x_axis.cross(lattice.y_axis);
  const int n = static_cast<int>(std::floor(lattice.extent / lattice.square_size));
  const double margin = params.search_radius_px + 2.0;

  Eigen::Isometry3d pose = opticalFromWorld(scan.sensor_pose);
  for (int round = 0; round < 2; ++round) {
    // Each corner with the centres of its four squares (i +- 1/2, j +- 1/2):
    // where the pattern's light and dark must show, whatever the perspective.
    std::vector<cv::Point3f> object, probes;
    std::vector<Eigen::Vector3d> optical;
    const auto at = [&](double i, double j) {
      return Eigen::Vector3d(lattice.origin + lattice.square_size * (i * lattice.x_axis + j * lattice.y_axis));
    };
    const auto point = [](const Eigen::Vector3d& w) {
      return cv::Point3f(static_cast<float>(w.x()), static_cast<float>(w.y()), static_cast<float>(w.z()));
    };
    const Eigen::Vector3d eye = pose.inverse() * Eigen::Vector3d::Zero();
    for (int i = -n; i <= n; ++i)
      for (int j = -n; j <= n; ++j) {
        const Eigen::Vector3d w = at(i, j);
        const Eigen::Vector3d c = pose * w;
        // Only corners in front of the camera, on the board's seen side.
        if (c.z() <= 0.05 || normal.dot(eye - w) <= 0.0) continue;
        object.push_back(point(w));
        optical.push_back(c);
        for (const auto& [di, dj] : {std::pair{0.5, 0.5}, {-0.5, 0.5}, {-0.5, -0.5}, {0.5, -0.5}})
          probes.push_back(point(at(i + di, j + dj)));
      }
    if (object.empty()) return result;
    cv::Mat rvec, tvec, rm;
    cv::eigen2cv(Eigen::Matrix3d(pose.linear()), rm);
    cv::Rodrigues(rm, rvec);
    tvec = (cv::Mat_<double>(3, 1) << pose.translation().x(), pose.translation().y(), pose.translation().z());
    std::vector<cv::Point2f> predicted, quadrant;
    cv::projectPoints(object, rvec, tvec, k, d, predicted);
    cv::projectPoints(probes, rvec, tvec, k, d, quadrant);

    std::vector<cv::Point3f> used_object;
    std::vector<cv::Point2f> used_image;
    for (std::size_t c = 0; c < predicted.size(); ++c) {
      const cv::Point2f p = predicted[c];
      if (p.x < margin || p.y < margin || p.x > grey.cols - 1 - margin || p.y > grey.rows - 1 - margin) continue;
      // Hidden by something nearer than the board (the object), per the range image.
      const int col = static_cast<int>(std::lround(p.x)), row = static_cast<int>(std::lround(p.y));
      if (col < scan.width && row < scan.height) {
        const float measured = scan.range[static_cast<std::size_t>(row) * scan.width + col];
        const double expected = scan.range_is_depth ? optical[c].z() : optical[c].norm();
        if (measured > 0.0f && measured < expected - params.occlusion_margin) continue;
      }
      // The window must stay inside the corner's four squares: at most half
      // the distance to the nearest square centre.
      double reach = 1e9;
      for (int q = 0; q < 4; ++q) {
        const cv::Point2f e = quadrant[4 * c + q] - p;
        reach = std::min(reach, std::sqrt(static_cast<double>(e.dot(e))));
      }
      const int window = std::min(params.search_radius_px, static_cast<int>(std::floor(0.7 * reach)));
      if (window < 2) continue;
      // A chequer corner: diagonal squares alike, neighbouring ones unlike.
      double v[4];
      bool inside = true;
      for (int q = 0; q < 4; ++q) inside = inside && (v[q] = sample(grey, quadrant[4 * c + q])) >= 0.0;
      if (!inside) continue;
      const double contrast = std::min({std::abs(v[0] - v[1]), std::abs(v[1] - v[2]), std::abs(v[2] - v[3]),
                                        std::abs(v[3] - v[0])});
      if (contrast < params.min_contrast || std::abs(v[0] - v[2]) > 0.5 * contrast ||
          std::abs(v[1] - v[3]) > 0.5 * contrast)
        continue;
      std::vector<cv::Point2f> refined{p};
      cv::cornerSubPix(grey, refined, cv::Size(window, window), cv::Size(-1, -1),
                       cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.01));
      const cv::Point2f r = refined.front();
      if (std::hypot(r.x - p.x, r.y - p.y) > window) continue;
      used_object.push_back(object[c]);
      used_image.push_back(r);
    }
    if (static_cast<int>(used_object.size()) < params.min_corners) return result;
    if (!cv::solvePnP(used_object, used_image, k, d, rvec, tvec, true, cv::SOLVEPNP_ITERATIVE)) return result;
    std::vector<cv::Point2f> reprojected;
    cv::projectPoints(used_object, rvec, tvec, k, d, reprojected);
    double sum = 0.0;
    for (std::size_t c = 0; c < reprojected.size(); ++c) {
      const cv::Point2f e = reprojected[c] - used_image[c];
      sum += e.dot(e);
    }
    cv::Rodrigues(rvec, rm);
    Eigen::Matrix3d rotation;
    cv::cv2eigen(rm, rotation);
    pose.linear() = rotation;
    pose.translation() = Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
    result.corners = used_object.size();
    result.rms_px = std::sqrt(sum / static_cast<double>(reprojected.size()));
  }
  result.found = result.rms_px <= params.max_rms_px;
  result.sensor_pose = sensorPoseFromOptical(pose);
  return result;
}

}  // namespace icrkit::reconstruction
