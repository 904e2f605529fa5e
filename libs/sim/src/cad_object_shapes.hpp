#pragma once
/// \file
/// The CAD objects as signed distance functions with the sampling grid each
/// is meshed on (internal to icrkit::sim; dimensions and construction in
/// docs/cad_objects.md).
///
/// Each shape is given in its design frame: z up, standing on z = 0, the
/// solid of revolution (if any) about the z axis. makeCadObject() meshes it
/// and then moves the mesh into the object frame of cad_objects.hpp.

#include "implicit_surface_mesher.hpp"

#include <icrkit/sim/cad_objects.hpp>

#include <Eigen/Geometry>

namespace icrkit::sim {

struct CadShape {
  ScalarField field;            ///< metres, negative inside, design frame
  Eigen::AlignedBox3d bounds;   ///< holds the solid, design frame
  double cell = 0.0;            ///< grid cell size (m): sets the vertex count
  Eigen::Vector3d anchor = Eigen::Vector3d::Zero();  ///< a grid node, design frame
};

CadShape cadShape(CadObject object);

/// The grid a shape is meshed on.
SampleGrid cadShapeGrid(const CadShape& shape);

}  // namespace icrkit::sim
