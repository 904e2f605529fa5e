#pragma once
/// \file
/// The camera pose from a checkerboard that the object partly hides (the
/// paper's setup B: the object stands on a checkerboard support). OpenCV's
/// findChessboardCorners needs the whole board; here the reported pose
/// predicts where each lattice corner of the board must appear, each visible
/// one is refined to sub-pixel accuracy (cv::cornerSubPix) and checked to be
/// a true chequer corner, and cv::solvePnP turns the found corners into the
/// camera pose. Two rounds (predict, refine, solve), so that a reported pose
/// a few millimetres off still lands every corner inside its search window.
///
/// The board is a lattice in the object frame: corners at origin + i s x +
/// j s y (s = square size), within `extent` of the origin. Corners where the
/// range image sees something nearer than the board (the object) are skipped.

#include <icrkit/reconstruction/input/rawlog_reader.hpp>

#include <Eigen/Geometry>

#include <cstddef>

namespace icrkit::reconstruction {

struct BoardLattice {
  double square_size = 0.02;                               ///< metres
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();        ///< one lattice corner, object frame (metres)
  Eigen::Vector3d x_axis = Eigen::Vector3d::UnitX();       ///< along a row of squares (unit)
  Eigen::Vector3d y_axis = Eigen::Vector3d::UnitY();       ///< along a column (unit, orthogonal to x_axis)
  double extent = 0.3;                                     ///< metres: corners considered around the origin
};

struct LatticePoseParameters {
  int search_radius_px = 5;       ///< cornerSubPix half window; predictions must be closer than this
  int min_corners = 12;           ///< fewer found corners: no pose
  double max_rms_px = 0.8;        ///< reprojection RMS above this: no pose
  double min_contrast = 40.0;     ///< grey levels between the light and dark quadrants of a corner
  double occlusion_margin = 0.01; ///< metres: a range this much nearer than the board hides the corner
};

struct LatticePose {
  bool found = false;
  Eigen::Isometry3d sensor_pose = Eigen::Isometry3d::Identity();  ///< object frame, MRPT sensor axes
  std::size_t corners = 0;   ///< corners used by the final solvePnP
  double rms_px = 0.0;       ///< their reprojection RMS
};

/// Needs the scan's intensity image (grey or RGB) and its camera; returns
/// found = false when the board is not seen well enough. Throws InputError
/// for a lattice with a square size <= 0 or axes that are not orthonormal.
LatticePose latticeCameraPose(const RangeScan& scan, const BoardLattice& lattice,
                              const LatticePoseParameters& params = {});

}  // namespace icrkit::reconstruction
