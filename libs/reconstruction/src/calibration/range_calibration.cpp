#include <icrkit/reconstruction/calibration/range_calibration.hpp>

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/ray_caster.hpp>

#include <nlohmann/json.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <vector>

namespace icrkit::reconstruction {

namespace {

constexpr double kTwoPi = 6.283185307179586;

// The regressors of e(r): [1, r, sin, cos] (the last two only with a wavelength).
Eigen::Matrix<double, 4, 1> regressors(double r, double wavelength) {
  Eigen::Matrix<double, 4, 1> x;
  x << 1.0, r, 0.0, 0.0;
  if (wavelength > 0) {
    x(2) = std::sin(kTwoPi * r / wavelength);
    x(3) = std::cos(kTwoPi * r / wavelength);
  }
  return x;
}

// The ray's range in the scan's own kind (ray length, or depth along the
// optical axis = MRPT's +x).
double rangeKind(const RangeScan& scan, const Eigen::Vector3d& direction, double length) {
  if (!scan.range_is_depth) return length;
  return length * direction.dot(scan.sensor_pose.rotation().col(0));
}

}  // namespace

double RangeErrorModel::error(double range) const {
  const Eigen::Matrix<double, 4, 1> x = regressors(range, wavelength);
  return offset * x(0) + slope * x(1) + sine * x(2) + cosine * x(3);
}

bool RangeErrorModel::isZero() const { return offset == 0 && slope == 0 && sine == 0 && cosine == 0; }

RangeCalibrationResult calibrateRangeError(const std::string& rawlog, const RawlogReaderOptions& options,
                                           const TriangleMesh& scene, const RangeCalibrationParameters& params) {
  if (!(params.wavelength >= 0) || !std::isfinite(params.wavelength))
    throw InputError("wavelength", "", "expected 0 (no periodic term) or a length in metres");
  if (!(params.max_residual > 0)) throw InputError("max_residual", "", "expected a positive length in metres");
  if (scene.faces.empty()) throw InputError("scene mesh", "", "has no faces to cast rays at");
  const RayCaster caster(scene);
  const std::size_t stride = std::max<std::size_t>(1, params.pixel_stride);

  // Normal equations of the least-squares fit, accumulated scan by scan.
  Eigen::Matrix4d ata = Eigen::Matrix4d::Zero();
  Eigen::Vector4d atb = Eigen::Vector4d::Zero();
  std::vector<std::pair<double, double>> samples;  // (measured range, residual)
  RangeCalibrationResult result;
  RangeCalibrationReport& report = result.report;
  report.min_range_m = std::numeric_limits<double>::infinity();
  report.max_range_m = 0.0;
  RawlogReader reader(rawlog, options);
  while (auto scan = reader.next()) {
    ++report.scans;
    const Eigen::Vector3d origin = scan->sensor_pose.translation();
    std::vector<Ray> rays;
    std::vector<std::size_t> which;
    for (std::size_t k = 0; k < scan->points.size(); k += stride) {
      Ray ray;
      ray.origin = origin;
      ray.direction = (scan->points[k] - origin).normalized();
      rays.push_back(ray);
      which.push_back(k);
    }
    const std::vector<RayHit> hits = caster.closestHits(rays);
    for (std::size_t i = 0; i < hits.size(); ++i) {
      const std::size_t k = which[i];
      const double measured = scan->range[scan->pixels[k]];
      if (!hits[i].hit) {
        ++report.rejected;
        continue;
      }
      const double reference = rangeKind(*scan, rays[i].direction, hits[i].distance);
      const double residual = measured - reference;
      if (!(std::abs(residual) <= params.max_residual)) {
        ++report.rejected;
        continue;
      }
      const Eigen::Matrix<double, 4, 1> x = regressors(measured, params.wavelength);
      ata += x * x.transpose();
      atb += x * residual;
      samples.emplace_back(measured, residual);
      report.min_range_m = std::min(report.min_range_m, measured);
      report.max_range_m = std::max(report.max_range_m, measured);
    }
  }
  report.samples = samples.size();
  if (samples.size() < 100)
    throw InputError(rawlog, "", "only " + std::to_string(samples.size()) +
                                     " pixels hit the reference scene within the residual limit; expected a recording "
                                     "of that scene at its true poses");
  // The linear and the periodic terms separate only over a range span of a
  // good part of a wavelength; below that the slope is left out.
  const bool with_slope = report.max_range_m - report.min_range_m > 0.25 * std::max(params.wavelength, 0.4);
  std::vector<int> columns{0};
  if (with_slope) columns.push_back(1);
  if (params.wavelength > 0) {
    columns.push_back(2);
    columns.push_back(3);
  }
  const int m = static_cast<int>(columns.size());
  Eigen::MatrixXd a(m, m);
  Eigen::VectorXd b(m);
  for (int i = 0; i < m; ++i) {
    b(i) = atb(columns[i]);
    for (int j = 0; j < m; ++j) a(i, j) = ata(columns[i], columns[j]);
  }
  const Eigen::VectorXd solution = a.ldlt().solve(b);
  if (!solution.allFinite()) throw InputError(rawlog, "", "the range error fit is singular (too few distinct ranges)");
  Eigen::Vector4d coefficients = Eigen::Vector4d::Zero();
  for (int i = 0; i < m; ++i) coefficients(columns[i]) = solution(i);
  RangeErrorModel& model = result.model;
  model.wavelength = params.wavelength;
  model.offset = coefficients(0);
  model.slope = coefficients(1);
  model.sine = coefficients(2);
  model.cosine = coefficients(3);

  double before = 0.0, after = 0.0;
  for (const auto& [measured, residual] : samples) {
    before += residual * residual;
    const double corrected = residual - model.error(measured);
    after += corrected * corrected;
  }
  report.rms_before_m = std::sqrt(before / double(samples.size()));
  report.rms_after_m = std::sqrt(after / double(samples.size()));
  return result;
}

std::size_t correctRange(RangeScan& scan, const RangeErrorModel& model) {
  if (model.isZero()) return 0;
  // Points first, from the measured ranges: each moves along its ray by
  // the ratio of corrected to measured range (a depth and a ray length
  // scale alike along one ray).
  const Eigen::Vector3d origin = scan.sensor_pose.translation();
  for (std::size_t k = 0; k < scan.points.size(); ++k) {
    const double measured = scan.range[scan.pixels[k]];
    const double corrected = measured - model.error(measured);
    if (measured > 0 && corrected > 0) scan.points[k] = origin + (scan.points[k] - origin) * (corrected / measured);
  }
  std::size_t invalidated = 0;
  for (float& r : scan.range) {
    if (!(r > 0)) continue;
    const double corrected = double(r) - model.error(double(r));
    if (corrected > 0) {
      r = static_cast<float>(corrected);
    } else {
      r = 0.0f;
      ++invalidated;
    }
  }
  scan.dropInvalidPoints();
  return invalidated;
}

void writeRangeErrorModel(const std::string& path, const RangeErrorModel& model, const RangeCalibrationReport& report) {
  const nlohmann::json json{{"format", "icrkit range error model 1"},
                            {"model", "e(r) = offset + slope r + sine sin(2 pi r / wavelength) + cosine cos(2 pi r / "
                                      "wavelength); corrected r' = r - e(r); metres"},
                            {"wavelength_m", model.wavelength},
                            {"offset_m", model.offset},
                            {"slope", model.slope},
                            {"sine_m", model.sine},
                            {"cosine_m", model.cosine},
                            {"calibration",
                             {{"scans", report.scans},
                              {"samples", report.samples},
                              {"rejected", report.rejected},
                              {"min_range_m", report.min_range_m},
                              {"max_range_m", report.max_range_m},
                              {"rms_before_m", report.rms_before_m},
                              {"rms_after_m", report.rms_after_m}}}};
  writeFileAtomically(path, [&](std::ostream& out) { out << json.dump(2) << '\n'; }, false);
}

RangeErrorModel readRangeErrorModel(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "", "cannot open the range error model");
  nlohmann::json json;
  try {
    in >> json;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, "", std::string("not JSON: ") + e.what());
  }
  // value() would throw a type error for a "format" that is not a string.
  if (!json.is_object() || !json.contains("format") || !json["format"].is_string() ||
      json["format"].get<std::string>() != "icrkit range error model 1")
    throw InputError(path, "format", "expected \"icrkit range error model 1\" (written by icrkit calibrate-range)");
  RangeErrorModel model;
  auto number = [&](const char* key, double& value) {
    if (!json.contains(key) || !json[key].is_number()) throw InputError(path, key, "expected a number");
    value = json[key].get<double>();
    if (!std::isfinite(value)) throw InputError(path, key, "expected a finite number");
  };
  number("wavelength_m", model.wavelength);
  number("offset_m", model.offset);
  number("slope", model.slope);
  number("sine_m", model.sine);
  number("cosine_m", model.cosine);
  if (model.wavelength < 0) throw InputError(path, "wavelength_m", "expected 0 or a positive length");
  return model;
}

}  // namespace icrkit::reconstruction
