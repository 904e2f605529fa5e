#include <icrkit/reconstruction/meshing/ball_pivoting.hpp>

#include <icrkit/core/disjoint_sets.hpp>
#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/mesh_topology.hpp>
#include <icrkit/core/morton_order.hpp>

#include "hole_triangulation.hpp"
#include "layer_thinning.hpp"
#include "point_insertion.hpp"
#include "point_grid.hpp"

#include <Eigen/Geometry>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <deque>
#include <array>
#include <limits>
#include <optional>
#include <string>

namespace icrkit::reconstruction {
namespace {

using Eigen::Vector3d;

// A strictly increasing function of the angle atan2(sine, cosine) taken
// in [0, 2 pi), with values in [0, 4): the ball's rotation compared without
// a call to atan2. A point on the old ball's sphere (a planar quad's fourth
// corner) can come out a hair below 0; it is the very first one touched.
double pivotAngle(double sine, double cosine) {
  if (sine >= 0.0) {
    if (cosine >= 0.0) return sine + cosine > 0.0 ? sine / (sine + cosine) : 0.0;
    return 1.0 - cosine / (sine - cosine);
  }
  if (cosine > 0.0 && -sine <= 1e-9 * cosine) return 0.0;
  if (cosine < 0.0) return 2.0 - sine / (-sine - cosine);
  return 3.0 + cosine / (cosine - sine);
}

// Centre of the ball of radius rho through a, b, c on the side the winding
// a -> b -> c faces (right-hand rule), if the triangle is not degenerate and
// its circumradius does not exceed rho.
std::optional<Vector3d> ballCentre(const Vector3d& a, const Vector3d& b, const Vector3d& c, double rho,
                                   Vector3d* unit_normal = nullptr) {
  const Vector3d ab = b - a, ac = c - a;
  const Vector3d n = ab.cross(ac);
  const double n2 = n.squaredNorm();
  // Relative test: a sliver whose area is negligible against its edges has
  // no well-defined ball.
  if (!(n2 > 1e-24 * ab.squaredNorm() * ac.squaredNorm())) return std::nullopt;
  const Vector3d to_circumcentre = (ac.squaredNorm() * n.cross(ab) + ab.squaredNorm() * ac.cross(n)) / (2.0 * n2);
  const double h2 = rho * rho - to_circumcentre.squaredNorm();
  if (h2 < 0.0) return std::nullopt;
  const Vector3d unit = n / std::sqrt(n2);
  if (unit_normal) *unit_normal = unit;
  return a + to_circumcentre + std::sqrt(h2) * unit;
}

struct Edge {
  int a, b;        // a < b
  int faces[2];    // -1 when absent
  int faceCount() const { return (faces[0] >= 0) + (faces[1] >= 0); }
};

class BallPivoter {
  struct Candidate {
    double angle;
    int k;
    Vector3d centre, normal;
  };
  struct Scratch {
    std::vector<const PointGrid::Entry*> near;
    std::vector<Candidate> candidates;
  };
  struct PivotResult {
    int k = -1;  // the point the ball rests on, -1: none
  };
  struct BatchItem {
    int edge = -1, i = -1, j = -1, o = -1, k = -1;
  };
  static constexpr std::size_t kBatch = 4096;
  static constexpr std::size_t kParallelBatch = 64;

public:
  // Works on a copy of the points in Morton order (`order` lists the input
  // index of each): the front then walks through memory about as it walks
  // over the surface, whatever order the input came in.
  BallPivoter(const PointCloud& cloud, std::vector<std::uint32_t> order, const BallPivotingParameters& params)
      : order_(std::move(order)), params_(params) {
    const std::size_t n = order_.size();
    p_.resize(n);
    normals_.resize(n);
    skipped_.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      p_[i] = cloud.positions[order_[i]];
      const Vector3d& normal = cloud.normals[order_[i]];
      // A point without a normal (a window too small for a plane fit, say)
      // has no side for the ball to stay on: it takes no part.
      if (normal.squaredNorm() > 0.0) {
        normals_[i] = normal.normalized();
      } else {
        normals_[i].setZero();
        skipped_[i] = 1;
        ++unoriented_;
      }
    }
    used_.assign(n, 0);
    open_edges_.assign(n, 0);
    vertex_edges_.resize(n);
  }

  std::size_t unorientedPoints() const { return unoriented_; }
  std::size_t foldedHoles() const { return folded_holes_; }
  const std::vector<std::uint8_t>& skipped() const { return skipped_; }

  // Leaves out the points `keep` does not flag (a thinned noise layer):
  // like duplicates they never become vertices and never block a ball.
  std::size_t markThinned(const std::vector<std::uint8_t>& keep) {
    std::size_t count = 0;
    for (std::size_t i = 0; i < p_.size(); ++i)
      if (!keep[i] && !skipped_[i]) {
        skipped_[i] = 1;
        ++count;
      }
    return count;
  }

  void run(const std::vector<double>& radii, BallPivotingReport& report) {
    for (std::size_t r = 0; r < radii.size(); ++r) {
      const auto start = std::chrono::steady_clock::now();
      rho_ = radii[r];
      // Pivot and seed queries reach at most 2 rho from their centre.
      grid_.build(p_, normals_, skipped_, 2.0 * rho_);
      BallPivotingPass pass;
      pass.radius = rho_;
      const std::size_t faces_before = faces_.size();
      // Edges on which a smaller ball stopped get another chance.
      if (r > 0)
        for (std::size_t e = 0; e < edges_.size(); ++e)
          if (edges_[e].faceCount() == 1) front_.push_back(static_cast<int>(e));
      expandFront();
      for (std::size_t v = 0; v < p_.size(); ++v) {
        if (used_[v] || skipped_[v]) continue;
        if (findSeed(static_cast<int>(v))) {
          ++pass.seeds;
          expandFront();
        }
      }
      pass.triangles = faces_.size() - faces_before;
      pass.time_ms = millisecondsSince(start);
      report.passes.push_back(pass);
    }
  }

  const std::vector<Vector3d>& positions() const { return p_; }

  // Marks every point that lies within `distance` of a point with a normal
  // and a smaller input index; `nearest` holds each point's nearest-neighbour distance, so
  // only the few points with a close neighbour are looked at.
  std::size_t markDuplicates(const std::vector<double>& nearest, double distance) {
    // Both points of a duplicate pair have a neighbour that close: only
    // those go into the grid.
    std::vector<std::uint8_t> far(p_.size());
    for (std::size_t i = 0; i < p_.size(); ++i) far[i] = !(nearest[i] <= distance);
    if (std::count(far.begin(), far.end(), 0) == 0) return 0;
    std::size_t count = 0;
    const PointGrid grid(p_, {}, far, std::max(distance, 1e-300));
    for (std::size_t i = 0; i < p_.size(); ++i) {
      if (far[i]) continue;
      // The group's representative is its first point that has a normal.
      bool duplicate = false;
      grid.forEachWithin(p_[i], distance, [&](const PointGrid::Entry& q, double) {
        if (order_[q.index] < order_[i] && normals_[q.index].squaredNorm() > 0.0) duplicate = true;
      });
      if (duplicate && !skipped_[i]) {
        skipped_[i] = 1;
        ++count;
      }
    }
    return count;
  }

  // Fills the holes the balls left: every simple boundary cycle of at most
  // `max_edges` edges and `max_perimeter` metres is triangulated over its
  // own vertices (triangulatePolygon) when the faces can agree with the
  // point normals and no chord is an edge already, so the mesh stays
  // edge-manifold and consistently oriented. Such holes remain where a
  // point off the surface (a stray sample, the noise layer of a fused
  // cloud) is the first one the ball touches. A hole that cannot be filled
  // as it is (a chord is an edge on the far side of a fold, a face would
  // face away from its normals) gets more chances: one, two, then three
  // rings of faces around it are taken out and the larger, cleaner hole is
  // filled instead, or they go back. Returns the number of holes filled.
  //
  // A larger hole, up to `seen_edges` edges, is filled only where the
  // surface was seen: every point of the fill (sampled at a third of
  // `support_distance`) must have an input point, used or not, within
  // `support_distance`. Such holes are where the noise layer kept the balls
  // out; an opening no view saw (an object's base) has no points inside.
  std::size_t fillHoles(std::size_t max_edges, double max_perimeter, std::size_t seen_edges,
                        double support_distance) {
    if (max_edges < 3 || !(max_perimeter > 0.0)) return 0;
    std::size_t filled = 0;
    std::vector<std::vector<int>> stubborn, stubborn_seen;
    support_distance_ = support_distance;
    for (const std::vector<int>& cycle : simpleBoundaryCycles()) {
      if (withinBounds(cycle, max_edges, max_perimeter)) {
        if (fillCycle(cycle, false)) ++filled;
        else stubborn.push_back(cycle);
      } else if (cycle.size() <= seen_edges && support_distance > 0.0) {
        if (fillCycle(cycle, true)) ++filled;
        else stubborn_seen.push_back(cycle);
      }
    }
    if (!stubborn.empty() || !stubborn_seen.empty()) {
      vertex_faces_.assign(p_.size(), {});
      for (std::size_t f = 0; f < faces_.size(); ++f)
        if (faces_[f][0] >= 0)
          for (int k = 0; k < 3; ++k) vertex_faces_[faces_[f][k]].push_back(static_cast<int>(f));
      for (const std::vector<int>& cycle : stubborn)
        if (isBoundaryCycle(cycle) && (refillAround(cycle, 3 * max_edges, 3.0 * max_perimeter, 1, false) ||
                                       refillAround(cycle, 3 * max_edges, 3.0 * max_perimeter, 2, false) ||
                                       refillAround(cycle, 3 * max_edges, 3.0 * max_perimeter, 3, false)))
          ++filled;
      // Seen holes the same way, the larger hole still checked against the
      // points.
      const double unbounded = std::numeric_limits<double>::infinity();
      for (const std::vector<int>& cycle : stubborn_seen)
        if (isBoundaryCycle(cycle) && (refillAround(cycle, seen_edges + 60, unbounded, 1, true) ||
                                       refillAround(cycle, seen_edges + 60, unbounded, 2, true)))
          ++filled;
      vertex_faces_.clear();
      refreshUse();
    }
    // Last, the folded holes: only what every strict fill above, with its
    // rings re-opened, left open.
    if (params_.fill_folded_holes && support_distance > 0.0) {
      labelPieces();
      for (const std::vector<int>& cycle : simpleBoundaryCycles())
        if ((withinBounds(cycle, max_edges, max_perimeter) || cycle.size() <= seen_edges) && fillFoldedCycle(cycle)) {
          ++filled;
          ++folded_holes_;
        }
      face_piece_.clear();
      piece_area_.clear();
      refreshUse();
    }
    front_.clear();  // the faces added here need no pivoting
    return filled;
  }

  // Takes out the faces of components with fewer than `min_faces` faces:
  // flakes of a noisy layer beside the surface. Returns how many went.
  std::size_t removeSmallComponents(std::size_t min_faces) {
    if (min_faces < 2) return 0;
    const std::vector<int> piece = facePieces();
    std::vector<std::size_t> size(p_.size(), 0);
    for (int root : piece)
      if (root >= 0) ++size[root];
    std::size_t removed = 0;
    for (std::size_t face = 0; face < faces_.size(); ++face)
      if (piece[face] >= 0 && size[piece[face]] < min_faces) {
        removeFace(static_cast<int>(face));
        ++removed;
      }
    if (removed) refreshUse();
    return removed;
  }

private:
  bool withinBounds(const std::vector<int>& cycle, std::size_t max_edges, double max_perimeter) const {
    if (cycle.size() > max_edges) return false;
    double perimeter = 0.0;
    for (std::size_t v = 0; v < cycle.size(); ++v) perimeter += (p_[cycle[(v + 1) % cycle.size()]] - p_[cycle[v]]).norm();
    return perimeter <= max_perimeter;
  }

  // Whether every side of `cycle` is still a boundary edge that a face runs
  // in the cycle's direction.
  bool isBoundaryCycle(const std::vector<int>& cycle) const {
    for (std::size_t v = 0; v < cycle.size(); ++v)
      if (!canUse(cycle[(v + 1) % cycle.size()], cycle[v]) || findEdge(cycle[v], cycle[(v + 1) % cycle.size()]) < 0)
        return false;
    return true;
  }

  // Whether every point of the faces (a, b, c) lies within
  // `support_distance_` of an input point.
  bool seen(const std::vector<std::array<int, 3>>& faces, const std::vector<int>& polygon) {
    if (!support_) support_.emplace(p_);
    const double step = support_distance_ / 3.0;
    for (const auto& t : faces) {
      const Vector3d& a = p_[polygon[t[0]]];
      const Vector3d& b = p_[polygon[t[1]]];
      const Vector3d& c = p_[polygon[t[2]]];
      const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
      const int n = std::max(1, static_cast<int>(std::ceil(longest / step)));
      for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
          const Vector3d q = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
          if (support_->nearestWithin(q, support_distance_) < 0) return false;
        }
    }
    return true;
  }

  // The hole's polygon over its own points: no chord may be an edge
  // already, so the mesh stays edge-manifold.
  PolygonTriangulation triangulateHole(const std::vector<int>& polygon, FillFacing facing) const {
    std::vector<Vector3d> positions, normals;
    for (int v : polygon) {
      positions.push_back(p_[v]);
      normals.push_back(normals_[v]);
    }
    return triangulatePolygon(
        positions, normals,
        [&](int x, int y) {
          if (polygon[x] == polygon[y]) return false;
          const int e = findEdge(polygon[x], polygon[y]);
          return e < 0 || edges_[e].faceCount() == 0;
        },
        facing);
  }

  bool fillCycle(const std::vector<int>& cycle, bool must_be_seen) {
    // The cycle runs as its faces run their edges; the hole's faces run
    // them the other way, so the polygon is the cycle reversed.
    const std::vector<int> polygon(cycle.rbegin(), cycle.rend());
    const PolygonTriangulation fill = triangulateHole(polygon, FillFacing::agree);
    if (!fill.found) return false;
    if (must_be_seen && !seen(fill.triangles, polygon)) return false;
    for (const auto& t : fill.triangles) addFace(polygon[t[0]], polygon[t[1]], polygon[t[2]]);
    return true;
  }

  // The last chance of a hole every strict fill left open: its rim folded
  // over (where two sheets of a noisy layer met, along a sharp edge), so no
  // fill faces its normals everywhere. It is closed anyway, disagreeing
  // faces allowed but penalised, when the fill lies on seen surface, covers
  // at most `folded_hole_max_share` of the piece of surface it joins (the
  // outer rim of a flake or of a small open sheet also winds against its
  // normals, and a fill over it would be a copy of the sheet turned round)
  // and repeats no face back to back. Needs labelPieces() first.
  bool fillFoldedCycle(const std::vector<int>& cycle) {
    const std::vector<int> polygon(cycle.rbegin(), cycle.rend());
    const PolygonTriangulation fill = triangulateHole(polygon, FillFacing::prefer_agreeing);
    if (!fill.found) return false;
    const int piece = rimPiece(cycle);
    if (piece < 0 || !(fillArea(fill.triangles, polygon) <= params_.folded_hole_max_share * piece_area_[piece]))
      return false;
    for (const auto& t : fill.triangles)
      if (hasFace(polygon[t[0]], polygon[t[1]], polygon[t[2]])) return false;
    if (!seen(fill.triangles, polygon)) return false;
    for (const auto& t : fill.triangles) addFace(polygon[t[0]], polygon[t[1]], polygon[t[2]]);
    face_piece_.resize(faces_.size(), piece);
    return true;
  }

  // Whether some face already has the points a, b, c (in any order).
  bool hasFace(int a, int b, int c) const {
    const int e = findEdge(a, b);
    if (e < 0) return false;
    for (int face : edges_[e].faces)
      if (face >= 0)
        for (int k = 0; k < 3; ++k)
          if (faces_[face][k] == c) return true;
    return false;
  }

  double triangleArea(int a, int b, int c) const { return 0.5 * (p_[b] - p_[a]).cross(p_[c] - p_[a]).norm(); }

  double fillArea(const std::vector<std::array<int, 3>>& faces, const std::vector<int>& polygon) const {
    double area = 0.0;
    for (const auto& t : faces) area += triangleArea(polygon[t[0]], polygon[t[1]], polygon[t[2]]);
    return area;
  }

  // Per face slot: a point of its connected piece (pieces touch through
  // shared points, as components are counted) standing for the piece; -1
  // for a removed face.
  std::vector<int> facePieces() const {
    DisjointSets sets(p_.size());
    for (const Triangle& f : faces_)
      if (f[0] >= 0)
        for (int k = 1; k < 3; ++k) sets.unite(static_cast<std::uint32_t>(f[0]), static_cast<std::uint32_t>(f[k]));
    std::vector<int> piece(faces_.size(), -1);
    for (std::size_t face = 0; face < faces_.size(); ++face)
      if (faces_[face][0] >= 0) piece[face] = static_cast<int>(sets.find(static_cast<std::uint32_t>(faces_[face][0])));
    return piece;
  }

  // Labels the faces' pieces connected across shared edges (a flake that
  // touches the surface at one point is a piece of its own) and sums their
  // areas.
  void labelPieces() {
    DisjointSets sets(faces_.size());
    for (const Edge& edge : edges_)
      if (edge.faces[0] >= 0 && edge.faces[1] >= 0)
        sets.unite(static_cast<std::uint32_t>(edge.faces[0]), static_cast<std::uint32_t>(edge.faces[1]));
    face_piece_.assign(faces_.size(), -1);
    piece_area_.assign(faces_.size(), 0.0);
    for (std::size_t face = 0; face < faces_.size(); ++face) {
      const Triangle& f = faces_[face];
      if (f[0] < 0) continue;
      face_piece_[face] = static_cast<int>(sets.find(static_cast<std::uint32_t>(face)));
      piece_area_[face_piece_[face]] += triangleArea(f[0], f[1], f[2]);
    }
  }

  // The piece whose face borders the first side of `cycle`; -1 for none.
  int rimPiece(const std::vector<int>& cycle) const {
    const int e = findEdge(cycle[0], cycle[1 % cycle.size()]);
    if (e < 0) return -1;
    for (int face : edges_[e].faces)
      if (face >= 0 && static_cast<std::size_t>(face) < face_piece_.size()) return face_piece_[face];
    return -1;
  }

  // `rings` rings of faces around the hole's points are taken out.
  bool refillAround(const std::vector<int>& cycle, std::size_t max_edges, double max_perimeter, int rings,
                    bool must_be_seen) {
    std::vector<int> ring, around(cycle);
    for (int r = 0; r < rings; ++r) {
      ring.clear();
      for (int v : around)
        for (int f : vertex_faces_[v])
          if (faces_[f][0] >= 0) ring.push_back(f);
      std::sort(ring.begin(), ring.end());
      ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
      around.clear();
      for (int f : ring)
        for (int k = 0; k < 3; ++k) around.push_back(faces_[f][k]);
      std::sort(around.begin(), around.end());
      around.erase(std::unique(around.begin(), around.end()), around.end());
    }
    std::vector<Triangle> saved;
    for (int f : ring) saved.push_back(faces_[f]);
    for (int f : ring) removeFace(f);
    // The larger hole's rim: the removed faces' edges that a kept face
    // still borders; it must be one clean cycle.
    std::vector<std::pair<int, int>> rim;
    for (const Triangle& f : saved)
      for (int k = 0; k < 3; ++k) {
        const int e = findEdge(f[k], f[(k + 1) % 3]);
        if (edges_[e].faceCount() != 1) continue;
        int i = -1, j = -1, o = -1;
        orientedEdge(edges_[e], i, j, o);
        rim.emplace_back(i, j);
      }
    std::sort(rim.begin(), rim.end());
    rim.erase(std::unique(rim.begin(), rim.end()), rim.end());
    const std::vector<std::vector<int>> walks = traceBoundaryLoops(rim);
    const bool clean = walks.size() == 1 && walks[0].size() == rim.size() &&
                       std::binary_search(rim.begin(), rim.end(), std::make_pair(walks[0].back(), walks[0].front())) &&
                       isBoundaryCycle(walks[0]);
    std::vector<int> seen(walks.empty() ? std::vector<int>{} : walks[0]);
    std::sort(seen.begin(), seen.end());
    const bool simple = std::adjacent_find(seen.begin(), seen.end()) == seen.end();
    if (clean && simple && withinBounds(walks[0], max_edges, max_perimeter) && fillCycle(walks[0], must_be_seen))
      return true;
    for (const Triangle& f : saved) addFace(f[0], f[1], f[2]);
    return false;
  }

public:
  // The boundary as simple cycles (no repeated vertex), each in the
  // direction its faces run its edges: a closed chain through a vertex
  // where holes touch is split there into the holes it joins.
  std::vector<std::vector<int>> simpleBoundaryCycles() const {
    std::vector<std::vector<int>> cycles;
    for (const std::vector<int>& walk : traceBoundaryLoops(boundaryHalfEdges())) {
      std::vector<int> stack;
      for (std::size_t v = 0; v <= walk.size(); ++v) {
        const int vertex = walk[v % walk.size()];
        const auto seen = std::find(stack.begin(), stack.end(), vertex);
        if (seen == stack.end()) {
          stack.push_back(vertex);
          continue;
        }
        if (stack.end() - seen >= 3) cycles.emplace_back(seen, stack.end());
        stack.erase(seen + 1, stack.end());
      }
    }
    return cycles;
  }

  // The edges with one face, each as that face runs it.
  std::vector<std::pair<int, int>> boundaryHalfEdges() const {
    std::vector<std::pair<int, int>> half_edges;
    for (const Edge& edge : edges_) {
      if (edge.faceCount() != 1) continue;
      int i = -1, j = -1, o = -1;
      orientedEdge(edge, i, j, o);
      half_edges.emplace_back(i, j);
    }
    return half_edges;
  }

  // Edge statistics and boundary loops from the front's own bookkeeping.
  void summarise(BallPivotingReport& report) const {
    std::vector<std::pair<int, int>> boundary = boundaryHalfEdges();
    report.boundary_edges = boundary.size();
    report.boundary_loops = traceBoundaryLoops(std::move(boundary)).size();
    report.non_manifold_edges = 0;  // an edge never takes a third face
    report.euler_characteristic = static_cast<long>(std::count(used_.begin(), used_.end(), 1)) -
                                  static_cast<long>(std::count_if(edges_.begin(), edges_.end(),
                                                                  [](const Edge& e) { return e.faceCount() > 0; })) +
                                  static_cast<long>(std::count_if(faces_.begin(), faces_.end(),
                                                                  [](const Triangle& f) { return f[0] >= 0; }));
  }

  /// The faces, in input indices.
  std::vector<Triangle> takeFaces() {
    faces_.erase(std::remove_if(faces_.begin(), faces_.end(), [](const Triangle& f) { return f[0] < 0; }),
                 faces_.end());
    for (Triangle& f : faces_)
      for (int k = 0; k < 3; ++k) f[k] = static_cast<int>(order_[static_cast<std::size_t>(f[k])]);
    return std::move(faces_);
  }

private:
  // The ball of radius rho at `centre` holds no usable point other than the
  // triangle's own. Points whose normals face away from the triangle are
  // ignored, so the two sides of a thin sheet do not block each other.
  // (Duplicates are not in the grid, so they never block a ball.)
  bool ballIsEmpty(const Vector3d& centre, const Vector3d& triangle_normal,
                   const std::vector<const PointGrid::Entry*>& near, int i, int j, int k) const {
    const double limit = rho_ * rho_ * (1.0 - 1e-9);
    for (const PointGrid::Entry* q : near) {
      const int qi = static_cast<int>(q->index);
      if (qi == i || qi == j || qi == k) continue;
      if ((q->position - centre).squaredNorm() < limit && q->normal.dot(triangle_normal) > 0.0) return false;
    }
    return true;
  }

  int findEdge(int a, int b) const {
    const int lo = std::min(a, b), hi = std::max(a, b);
    for (int e : vertex_edges_[lo])
      if (edges_[e].b == hi) return e;
    return -1;
  }

  // Whether the directed edge from -> to can be added to a new face: the
  // edge is new, or it borders exactly one face that runs it to -> from.
  bool canUse(int from, int to) const {
    const int e = findEdge(from, to);
    if (e < 0 || edges_[e].faceCount() == 0) return true;
    if (edges_[e].faceCount() != 1) return false;
    const Triangle& f = faces_[edges_[e].faces[0] >= 0 ? edges_[e].faces[0] : edges_[e].faces[1]];
    for (int k = 0; k < 3; ++k)
      if (f[k] == to && f[(k + 1) % 3] == from) return true;
    return false;
  }

  // A used vertex without an open edge is surrounded by triangles.
  bool isInner(int v) const { return used_[v] && open_edges_[v] == 0; }

  void attachEdge(int from, int to, int face) {
    int e = findEdge(from, to);
    if (e < 0) {
      e = static_cast<int>(edges_.size());
      edges_.push_back({std::min(from, to), std::max(from, to), {face, -1}});
      vertex_edges_[std::min(from, to)].push_back(e);
      ++open_edges_[from];
      ++open_edges_[to];
      front_.push_back(e);
      return;
    }
    Edge& edge = edges_[e];
    const int delta = edge.faceCount() == 0 ? 1 : -1;
    (edge.faces[0] < 0 ? edge.faces[0] : edge.faces[1]) = face;
    open_edges_[from] += delta;
    open_edges_[to] += delta;
  }

  void addFace(int a, int b, int c) {
    const int face = static_cast<int>(faces_.size());
    faces_.emplace_back(a, b, c);
    used_[a] = used_[b] = used_[c] = 1;
    attachEdge(a, b, face);
    attachEdge(b, c, face);
    attachEdge(c, a, face);
    if (!vertex_faces_.empty())
      for (int v : {a, b, c}) vertex_faces_[v].push_back(face);
  }

  // Takes a face out (after the pivoting: hole repair). Its slot stays, as
  // (-1, -1, -1), so that face indices keep their meaning; `used_` is
  // brought up to date by refreshUse().
  void removeFace(int face) {
    Triangle& f = faces_[face];
    for (int k = 0; k < 3; ++k) {
      const int from = f[k], to = f[(k + 1) % 3];
      Edge& edge = edges_[findEdge(from, to)];
      const int delta = edge.faceCount() == 2 ? 1 : -1;
      (edge.faces[0] == face ? edge.faces[0] : edge.faces[1]) = -1;
      open_edges_[from] += delta;
      open_edges_[to] += delta;
    }
    f = Triangle(-1, -1, -1);
  }

  void refreshUse() {
    std::fill(used_.begin(), used_.end(), 0);
    for (const Triangle& f : faces_)
      if (f[0] >= 0) used_[f[0]] = used_[f[1]] = used_[f[2]] = 1;
  }

  bool findSeed(int v) {
    grid_.entriesWithin(p_[v], 2.0 * rho_, near_);
    // Pair the closest orphans first: small triangles are the likeliest
    // to have an empty ball.
    seed_candidates_.clear();
    for (const PointGrid::Entry* q : near_) {
      const int qi = static_cast<int>(q->index);
      if (qi == v || used_[qi] || q->normal.dot(normals_[v]) <= 0.0) continue;
      seed_candidates_.push_back({(q->position - p_[v]).squaredNorm(), qi});
    }
    std::sort(seed_candidates_.begin(), seed_candidates_.end());
    if (seed_candidates_.size() > params_.seed_neighbours) seed_candidates_.resize(params_.seed_neighbours);
    for (std::size_t x = 0; x < seed_candidates_.size(); ++x)
      for (std::size_t y = x + 1; y < seed_candidates_.size(); ++y) {
        int a = seed_candidates_[x].second, b = seed_candidates_[y].second;
        if ((p_[a] - p_[v]).cross(p_[b] - p_[v]).dot(normals_[v]) < 0.0) std::swap(a, b);
        Vector3d normal;
        const auto centre = ballCentre(p_[v], p_[a], p_[b], rho_, &normal);
        if (!centre) continue;
        if (normal.dot(normals_[v]) <= 0.0 || normal.dot(normals_[a]) <= 0.0 || normal.dot(normals_[b]) <= 0.0)
          continue;
        if (!ballIsEmpty(*centre, normal, near_, v, a, b)) continue;
        addFace(v, a, b);
        return true;
      }
    return false;
  }

  // The face through the first point that the ball, pivoting around the
  // edge i -> j of face (i, j, o), touches: a pure function of the geometry
  // (not of the mesh built so far), so front edges can be pivoted in
  // parallel and their faces added in order afterwards.
  PivotResult pivot(int i, int j, int o, Scratch& scratch) const {
    PivotResult result;
    const auto old_centre = ballCentre(p_[i], p_[j], p_[o], rho_);
    if (!old_centre) return result;
    const Vector3d mid = 0.5 * (p_[i] + p_[j]);
    const Vector3d axis = (p_[j] - p_[i]).normalized();
    const Vector3d from = *old_centre - mid;
    // Every point the pivoting ball can touch, and every point that could
    // lie inside it, is within the centre circle's radius plus rho of mid.
    const double circle = std::sqrt(std::max(0.0, rho_ * rho_ - 0.25 * (p_[j] - p_[i]).squaredNorm()));
    grid_.entriesWithin(mid, circle + rho_, scratch.near);

    scratch.candidates.clear();
    const Vector3d ji = p_[i] - p_[j];
    const Vector3d& ni = normals_[i];
    const Vector3d& nj = normals_[j];
    for (const PointGrid::Entry* q : scratch.near) {
      const int k = static_cast<int>(q->index);
      if (k == i || k == j || k == o) continue;
      // Orientation first: it rejects the points behind the surface
      // before the costlier ball centre.
      const Vector3d n = ji.cross(q->position - p_[j]);
      if (n.dot(q->normal) <= 0.0 || n.dot(ni) <= 0.0 || n.dot(nj) <= 0.0) continue;
      Vector3d normal;
      const auto centre = ballCentre(p_[j], p_[i], q->position, rho_, &normal);
      if (!centre) continue;
      const Vector3d to = *centre - mid;
      scratch.candidates.push_back({pivotAngle(axis.dot(from.cross(to)), from.dot(to)), k, *centre, normal});
    }
    // In pivoting order; the first candidate nearly always has an empty
    // ball, so selecting minima beats sorting.
    auto earlier = [](const Candidate& x, const Candidate& y) {
      return x.angle != y.angle ? x.angle < y.angle : x.k < y.k;
    };
    auto& c = scratch.candidates;
    for (auto end = c.end(); end != c.begin(); --end) {
      const auto first = std::min_element(c.begin(), end, earlier);
      if (ballIsEmpty(first->centre, first->normal, scratch.near, i, j, first->k)) {
        result.k = first->k;
        break;
      }
      std::iter_swap(first, end - 1);
    }
    return result;
  }

  // The face (j, i, k) is added if the mesh stays edge-manifold and
  // consistently oriented; otherwise the edge stays a boundary edge for this
  // radius: the first point the ball rests on decides.
  void apply(int i, int j, int k) {
    if (k >= 0 && !isInner(k) && canUse(i, k) && canUse(k, j)) addFace(j, i, k);
  }

  // The face's edge runs i -> j; o is the face's third vertex.
  void orientedEdge(const Edge& edge, int& i, int& j, int& o) const {
    const Triangle& f = faces_[edge.faces[0] >= 0 ? edge.faces[0] : edge.faces[1]];
    for (int k = 0; k < 3; ++k)
      if (f[k] != edge.a && f[k] != edge.b) {
        o = f[k];
        i = f[(k + 1) % 3];
        j = f[(k + 2) % 3];
      }
  }

  void expandFront() {
    // Batches of front edges are pivoted in parallel and applied in queue
    // order; edges the batch creates join the queue behind it, exactly as
    // in the one-at-a-time algorithm, so the mesh does not depend on the
    // batch size or the thread count.
    while (!front_.empty()) {
      batch_.clear();
      while (!front_.empty() && batch_.size() < kBatch) {
        const int e = front_.front();
        front_.pop_front();
        if (edges_[e].faceCount() != 1) continue;
        BatchItem item;
        item.edge = e;
        orientedEdge(edges_[e], item.i, item.j, item.o);
        batch_.push_back(item);
      }
      auto pivotRange = [&](std::size_t begin, std::size_t end) {
        Scratch& scratch = scratch_.local();
        for (std::size_t b = begin; b != end; ++b) batch_[b].k = pivot(batch_[b].i, batch_[b].j, batch_[b].o, scratch).k;
      };
      // A young front (a fresh seed's three edges) is not worth a task.
      if (batch_.size() < kParallelBatch)
        pivotRange(0, batch_.size());
      else
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, batch_.size(), 32),
                          [&](const tbb::blocked_range<std::size_t>& range) { pivotRange(range.begin(), range.end()); });
      for (const BatchItem& item : batch_)
        if (edges_[item.edge].faceCount() == 1) apply(item.i, item.j, item.k);
    }
  }

  std::vector<std::uint32_t> order_;
  std::vector<Vector3d> p_, normals_;
  PointGrid grid_;
  const BallPivotingParameters& params_;
  double rho_ = 0.0;

  std::vector<std::uint8_t> used_, skipped_;  // skipped: duplicates and points without a normal
  std::size_t unoriented_ = 0;
  std::vector<int> open_edges_;           // per vertex: incident edges with one face
  std::vector<std::vector<int>> vertex_edges_;  // per vertex: edges whose smaller end it is
  std::vector<std::vector<int>> vertex_faces_;  // per vertex: its faces, during hole repair only
  std::optional<KdTree> support_;               // every input point, for holes that must have been seen
  double support_distance_ = 0.0;
  std::vector<int> face_piece_;     // folded-hole pass: per face, its edge-connected piece (a face index)
  std::vector<double> piece_area_;  // per piece: its area (m^2)
  std::size_t folded_holes_ = 0;
  std::vector<Edge> edges_;
  std::vector<Triangle> faces_;
  std::deque<int> front_;

  std::vector<const PointGrid::Entry*> near_;
  std::vector<std::pair<double, int>> seed_candidates_;
  std::vector<BatchItem> batch_;
  tbb::enumerable_thread_specific<Scratch> scratch_;
};

// The layer's thickness is measured over windows of this many median
// spacings (wide enough to hold both faces of a noise layer several
// spacings thick; a quadric takes the curvature out), and the
// layer is thinned only when the cell it asks for exceeds this many
// spacings: a clean sample is left alone.
constexpr double kThicknessWindow = 6.0;
constexpr double kThinningThreshold = 1.5;
// Reinserted points keep this many median spacings (of the whole cloud)
// from each other and from the vertices already there.
constexpr double kInsertionSeparation = 0.35;

void validateInput(const PointCloud& cloud) {
  if (cloud.size() < 3)
    throw InputError("point cloud", "", "ball pivoting needs at least 3 points, got " + std::to_string(cloud.size()));
  if (!cloud.hasNormals())
    throw InputError("point cloud", "", "ball pivoting needs oriented normals (nx, ny, nz); the cloud has none");
  std::size_t oriented = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!cloud.positions[i].allFinite())
      throw InputError("point cloud", "point " + std::to_string(i), "non-finite coordinate, expected finite x, y, z");
    const Vector3d& n = cloud.normals[i];
    if (!n.allFinite()) throw InputError("point cloud", "point " + std::to_string(i), "the normal must be finite");
    oriented += n.squaredNorm() > 0.0;
  }
  if (oriented < 3)
    throw InputError("point cloud", "",
                     "ball pivoting needs at least 3 points with a non-zero normal, got " + std::to_string(oriented));
}

// The spacing statistics the automatic radii use.
struct Spacing {
  double median = 0.0;  // of the nearest-neighbour distances
  double p90 = 0.0;     // their 90th percentile
};

Spacing spacingOf(std::vector<double> nearest) {
  Spacing s;
  if (nearest.size() < 2) return s;
  s.median = spacingStatistics(nearest).median;
  const auto at = nearest.begin() + static_cast<std::ptrdiff_t>(nearest.size() * 9 / 10);
  std::nth_element(nearest.begin(), at, nearest.end());
  s.p90 = *at;
  return s;
}

bool anyRelative(const std::vector<Length>& radii) {
  return std::any_of(radii.begin(), radii.end(), [](const Length& r) { return r.relative; });
}

std::vector<double> radiiFor(const BallPivotingParameters& params, const Spacing& spacing_stats) {
  const double spacing = spacing_stats.median;
  const bool relative = anyRelative(params.radii);
  if (relative && !(spacing > 0.0))
    throw InputError("BallPivotingParameters::radii", "",
                     "the median point spacing is 0 (more than half the points are duplicates); give radii in "
                     "metres");
  std::vector<double> radii;
  for (const Length& r : params.radii) radii.push_back(r.metresFor(spacing));
  const bool all_relative =
      std::all_of(params.radii.begin(), params.radii.end(), [](const Length& r) { return r.relative; });
  const double gap = params.gap_radius_factor * spacing_stats.p90;
  if (all_relative && params.gap_radius_factor > 0.0 && std::isfinite(gap) && gap > 3.0 * spacing) radii.push_back(gap);
  for (double r : radii)
    if (!std::isfinite(r) || !(r > 0.0))
      throw InputError("BallPivotingParameters::radii", "", "a radius must be finite and > 0 m, got " + std::to_string(r));
  std::sort(radii.begin(), radii.end());
  radii.erase(std::unique(radii.begin(), radii.end()), radii.end());
  return radii;
}

}  // namespace

std::vector<double> ballPivotingRadii(const PointCloud& cloud, const BallPivotingParameters& params) {
  params.validate();
  return radiiFor(params,
                  anyRelative(params.radii) ? spacingOf(nearestNeighbourDistances(cloud.positions)) : Spacing{});
}

void BallPivotingParameters::validate() const {
  const auto finite_non_negative = [](double v) { return std::isfinite(v) && v >= 0.0; };
  if (radii.empty()) throw InputError("BallPivotingParameters::radii", "", "give at least one radius");
  for (const Length& r : radii)
    if (!r.valid())
      throw InputError("BallPivotingParameters::radii", "", "a radius must be finite and > 0, got " + formatLength(r));
  if (!finite_non_negative(gap_radius_factor))
    throw InputError("BallPivotingParameters::gap_radius_factor", "", "expected a finite factor >= 0 (0 = never)");
  if (duplicate_distance && !finite_non_negative(*duplicate_distance))
    throw InputError("BallPivotingParameters::duplicate_distance", "", "expected a finite distance >= 0 in metres");
  if (!finite_non_negative(thinning_factor))
    throw InputError("BallPivotingParameters::thinning_factor", "", "expected a finite factor >= 0 (0 = off)");
  if (!finite_non_negative(hole_perimeter_factor))
    throw InputError("BallPivotingParameters::hole_perimeter_factor", "", "expected a finite factor >= 0");
  if (!finite_non_negative(folded_hole_max_share))
    throw InputError("BallPivotingParameters::folded_hole_max_share", "", "expected a finite share >= 0");
}

BallPivotingResult ballPivoting(const PointCloud& cloud, const BallPivotingParameters& params) {
  params.validate();
  validateInput(cloud);
  const double duplicate_distance = params.duplicate_distance.value_or(1e-9 * cloud.bounds().diagonal().norm());
  const std::vector<std::uint32_t> order = mortonOrder(cloud.positions);
  BallPivoter pivoter(cloud, order, params);
  const std::vector<double> nearest = nearestNeighbourDistances(pivoter.positions());
  const Spacing spacing_stats = spacingOf(nearest);
  const double spacing = spacing_stats.median;

  BallPivotingResult result;
  BallPivotingReport& report = result.report;
  report.points = cloud.size();
  report.median_spacing = spacing;

  report.duplicate_points = pivoter.markDuplicates(nearest, duplicate_distance);
  report.unoriented_points = pivoter.unorientedPoints();
  Spacing mesh_spacing = spacing_stats;
  std::vector<std::size_t> thinned;  // input indices
  if (params.thinning_factor > 0.0 && spacing > 0.0) {
    report.layer_thickness = layerThickness(pivoter.positions(), pivoter.skipped(), kThicknessWindow * spacing);
    const double cell = params.thinning_factor * report.layer_thickness;
    if (cell > kThinningThreshold * spacing) {
      report.thinning_cell = cell;
      const std::vector<std::uint8_t> before = pivoter.skipped();
      report.thinned_points = pivoter.markThinned(thinToCells(pivoter.positions(), before, cell));
      for (std::size_t i = 0; i < before.size(); ++i)
        if (!before[i] && pivoter.skipped()[i]) thinned.push_back(order[i]);
      std::sort(thinned.begin(), thinned.end());
      std::vector<Vector3d> kept;
      for (std::size_t i = 0; i < pivoter.positions().size(); ++i)
        if (!pivoter.skipped()[i]) kept.push_back(pivoter.positions()[i]);
      mesh_spacing = spacingOf(nearestNeighbourDistances(kept));
    }
  }
  report.mesh_spacing = mesh_spacing.median;
  const std::vector<double> radii = radiiFor(params, mesh_spacing);
  pivoter.run(radii, report);
  if (!std::isfinite(params.hole_perimeter_factor))
    throw InputError("hole_perimeter_factor", "", "must be finite");
  if (!(params.folded_hole_max_share >= 0.0) || !std::isfinite(params.folded_hole_max_share))
    throw InputError("folded_hole_max_share", "", "must be finite and >= 0");
  report.closed_holes = pivoter.fillHoles(params.close_holes_up_to, params.hole_perimeter_factor * radii.back(),
                                          params.seen_holes_up_to, radii.back());
  report.folded_holes = pivoter.foldedHoles();
  report.removed_faces = pivoter.removeSmallComponents(params.min_component_faces);
  pivoter.summarise(report);

  result.mesh.vertices = cloud;
  result.mesh.faces = pivoter.takeFaces();
  if (params.reinsert_thinned && !thinned.empty()) {
    // The layer's points lie within a few thicknesses of the mesh over the
    // kept ones; half a cell is several thicknesses (the cell is
    // `thinning_factor` of them) and well short of a thin wall's far side.
    PointInsertionParameters insertion;
    insertion.max_offset = 0.5 * report.thinning_cell;
    insertion.min_separation = kInsertionSeparation * spacing;
    report.reinserted_points = insertPointsIntoMesh(result.mesh, thinned, insertion).inserted;
    // Split sides of holes add boundary edges (loops and the Euler
    // characteristic stay); counted on the final mesh, which also checks
    // that the insertion kept every edge manifold.
    const EdgeStatistics edges = edgeStatistics(result.mesh);
    report.boundary_edges = edges.boundary_edges;
    report.non_manifold_edges = edges.non_manifold_edges;
  }
  const MeshComponents components = meshComponents(result.mesh);
  report.triangles = result.mesh.faces.size();
  report.unused_points = components.unreferenced_vertices;
  report.used_points = report.points - report.unused_points;
  report.components = components.count;
  return result;
}

}  // namespace icrkit::reconstruction
