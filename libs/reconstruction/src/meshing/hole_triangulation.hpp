#pragma once
// Minimum-weight triangulation of a hole's boundary polygon (the dynamic
// programme of Barequet and Sharir, as used by Liepa's hole filling): no new
// vertices, so a filled mesh's vertices stay the input points.

#include <Eigen/Core>

#include <array>
#include <functional>
#include <vector>

namespace icrkit::reconstruction {

struct PolygonTriangulation {
  bool found = false;
  /// Triangles as indices into the polygon, each wound w_i -> w_k -> w_j
  /// with i < k < j, i.e. in the polygon's own direction.
  std::vector<std::array<int, 3>> triangles;
};

/// How a fill's faces must face the corners' normals.
enum class FillFacing {
  /// Every face agrees (positive dot product) with its corners' mean normal.
  agree,
  /// Faces that disagree are allowed at a cost (a hole whose rim is folded
  /// over, where no fill can agree everywhere); the caller must check the
  /// fill against the surface some other way.
  prefer_agreeing,
};

/// Triangulates the closed polygon w_0 -> w_1 -> ... -> w_{n-1} -> w_0
/// (n >= 3). Each triangle's normal (right-hand rule in that winding) must
/// agree (positive dot product) with the mean of its corners' unit normals
/// (with FillFacing::prefer_agreeing: should; a disagreeing face weighs up to
/// 3 x its area), and
/// every chord (w_a, w_b) that is not a polygon side must satisfy
/// `chord_allowed(a, b)` (a < b); among the triangulations that qualify the
/// one of least sum of area x (2 - that agreement) is
/// returned, which prefers small faces that lie in the surface the normals
/// describe. O(n^3) time, O(n^2) memory.
PolygonTriangulation triangulatePolygon(const std::vector<Eigen::Vector3d>& positions,
                                        const std::vector<Eigen::Vector3d>& normals,
                                        const std::function<bool(int, int)>& chord_allowed,
                                        FillFacing facing = FillFacing::agree);

}  // namespace icrkit::reconstruction
