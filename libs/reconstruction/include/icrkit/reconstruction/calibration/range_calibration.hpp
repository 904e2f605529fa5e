#pragma once
/// \file
/// Time-of-flight range calibration: the systematic, range-dependent error
/// of a continuous-wave ToF camera ("wiggling": the modulation is not a
/// pure sinusoid), modelled as
///
///     e(r) = offset + slope r + a sin(2 pi r / wavelength) + b cos(2 pi r / wavelength)
///
/// and removed by r' = r - e(r) (Lindner and Kolb 2006; Fuchs and May 2008
/// fit the same kind of curve). The Krug et al. setup calibrated its SR4000
/// this way before scanning. The wavelength is a quarter of the
/// non-ambiguity range, c / (8 f): 1.249 m for the SR4000 at 30 MHz.
///
/// The reference is a recording of a known scene at known poses (a target
/// on a table, the simulator's scene.ply and ground truth): every valid
/// pixel's ray is cast against the scene mesh, and the difference between
/// the measured and the cast range is a sample of e(r).

#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/reconstruction/input/rawlog_reader.hpp>

#include <cstddef>
#include <string>

namespace icrkit::reconstruction {

struct RangeErrorModel {
  /// Metres; 0: no periodic term.
  double wavelength = 0.0;
  double offset = 0.0;  ///< metres
  double slope = 0.0;   ///< metres per metre
  double sine = 0.0;    ///< metres
  double cosine = 0.0;  ///< metres
  /// e(r) in metres for a range value r (the scan's own kind: a ray length
  /// for a ToF camera, a depth for a depth camera).
  double error(double range) const;
  bool isZero() const;
};

struct RangeCalibrationParameters {
  double wavelength = 1.249;  ///< metres, c / (8 f) of the camera's modulation frequency
  /// Samples whose measured range differs from the cast one by more than
  /// this (metres) are not the surface the ray was cast at (edges, mixed
  /// pixels, unmodelled objects) and are left out.
  double max_residual = 0.02;
  /// Every n-th valid pixel is used (the fit has 4-5 unknowns).
  std::size_t pixel_stride = 4;
};

struct RangeCalibrationReport {
  std::size_t scans = 0;
  std::size_t samples = 0;         ///< used in the fit
  std::size_t rejected = 0;        ///< beyond max_residual or no hit
  double min_range_m = 0.0, max_range_m = 0.0;
  double rms_before_m = 0.0;       ///< of the residuals, as measured
  double rms_after_m = 0.0;        ///< after the correction
};

struct RangeCalibrationResult {
  RangeErrorModel model;
  RangeCalibrationReport report;
};

/// Fits the model on every scan of `rawlog` (their poses from
/// `options.pose_file` when given: they must be the true ones) against
/// `scene` (same frame, metres). Throws InputError for no usable sample, a
/// range span too short to separate the terms, or bad parameters.
RangeCalibrationResult calibrateRangeError(const std::string& rawlog, const RawlogReaderOptions& options,
                                           const TriangleMesh& scene, const RangeCalibrationParameters& params = {});

/// Applies r' = r - e(r) to the range image and moves each point along its
/// ray accordingly; pixels whose corrected range is not positive become
/// invalid (their points are dropped). Returns how many were invalidated.
std::size_t correctRange(RangeScan& scan, const RangeErrorModel& model);

/// JSON file round trip (`{"format": "icrkit range error model 1", ...}`).
void writeRangeErrorModel(const std::string& path, const RangeErrorModel& model, const RangeCalibrationReport& report);
RangeErrorModel readRangeErrorModel(const std::string& path);

}  // namespace icrkit::reconstruction
