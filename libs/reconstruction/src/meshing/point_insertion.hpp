#pragma once
// Puts points that took no part in ball pivoting (the noise layer a
// thinning left out) back into the finished mesh as vertices: each point
// is projected onto the face nearest along that face's normal and the face
// is split around it. The mesh keeps its topology (each face is split
// within its own outline, as seen in its plane; boundary loops and
// components stay as they were), gains the points' density back, and every
// vertex is still an input point (positions are never moved, so the split
// faces follow the points up to `max_offset` off the old face's plane).

#include <icrkit/core/triangle_mesh.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace icrkit::reconstruction {

struct PointInsertionParameters {
  /// A point is inserted only into a face whose plane is at most this far
  /// away (metres) and whose normal agrees with the point's (positive dot
  /// product): a point of the wall's other side or an outlier stays out.
  double max_offset = 0.0;
  /// Inserted points keep at least this distance (metres, in the face's
  /// plane) from a corner, from each other and, unless they go onto it,
  /// from a face's edge; a point closer to an edge than this goes onto the
  /// edge (splitting both faces there), closer to a point it stays out. It
  /// avoids needle triangles around near-coincident points.
  double min_separation = 0.0;
  /// At most this many points go into one face (the first by index), so
  /// that a face over a dense clump costs a bounded time.
  std::size_t max_points_per_face = 256;
};

struct PointInsertionReport {
  std::size_t inserted = 0;    ///< points that became vertices
  std::size_t onto_edges = 0;  ///< of those: put onto an edge
  std::size_t left_out = 0;    ///< candidates that found no face or were too close to a vertex
};

/// The mesh's faces (counter-clockwise seen from the side the vertex
/// normals face) are replaced by the split faces; `candidates` are indices
/// of vertices that no face uses yet. Deterministic whatever the thread
/// count: a face's new triangles follow from its own points alone, and they
/// take its place in the face order.
PointInsertionReport insertPointsIntoMesh(TriangleMesh& mesh, const std::vector<std::size_t>& candidates,
                                          const PointInsertionParameters& params);

}  // namespace icrkit::reconstruction
