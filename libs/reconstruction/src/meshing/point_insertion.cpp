#include "point_insertion.hpp"

#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/mesh_topology.hpp>

#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <limits>
#include <tuple>

namespace icrkit::reconstruction {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

// A point closer than this many separations to a face's side (or beyond
// it) goes onto the side; the others stay inside the face. Wider bands put
// most points of a dense layer onto sides, where they crowd in one
// dimension; narrower ones only make thinner triangles along the sides.
constexpr double kEdgeBand = 0.25;
// Inside points keep this many separations from the face's outline.
constexpr double kOutlineClearance = 0.1;
// Attempts at a face's triangulation (each drops one inside point to blame)
// before it takes its side points only.
constexpr std::size_t kMaxAttempts = 32;

// A face's own plane: corner 0 at the origin, corner 1 on the first axis,
// the corners counter-clockwise, as the face is wound about its normal.
struct FaceFrame {
  Vector3d origin, e1, e2, normal;
  std::array<Vector2d, 3> corner;
  bool valid = false;

  Vector2d project(const Vector3d& p) const {
    const Vector3d d = p - origin;
    return {d.dot(e1), d.dot(e2)};
  }
};

FaceFrame frameOf(const std::vector<Vector3d>& p, const Triangle& f) {
  FaceFrame frame;
  const Vector3d ab = p[f[1]] - p[f[0]], ac = p[f[2]] - p[f[0]];
  const Vector3d n = ab.cross(ac);
  // Slivers have no plane worth projecting onto.
  if (!(n.squaredNorm() > 1e-20 * ab.squaredNorm() * ac.squaredNorm())) return frame;
  frame.origin = p[f[0]];
  frame.normal = n.normalized();
  frame.e1 = ab.normalized();
  frame.e2 = frame.normal.cross(frame.e1);
  for (int k = 0; k < 3; ++k) frame.corner[k] = frame.project(p[f[k]]);
  frame.valid = true;
  return frame;
}

double cross2(const Vector2d& a, const Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}
double orient(const Vector2d& a, const Vector2d& b, const Vector2d& c) {
  return cross2(b - a, c - a);
}

// Signed distance of x from each side of the triangle (side k runs from
// corner k to corner k + 1), positive inside.
std::array<double, 3> sideDistances(const std::array<Vector2d, 3>& c, const Vector2d& x) {
  std::array<double, 3> d{};
  for (int k = 0; k < 3; ++k) {
    const Vector2d& a = c[k];
    const Vector2d& b = c[(k + 1) % 3];
    const double length = (b - a).norm();
    d[k] = length > 0.0 ? orient(a, b, x) / length : -std::numeric_limits<double>::infinity();
  }
  return d;
}

// Where a candidate point goes: a face (side -1: inside it) or a side of it.
struct Placement {
  int face = -1;
  int side = -1;
  Vector2d xy = Vector2d::Zero();  // in the face's frame
  double t = 0.0;                  // along the side's edge, from its lower vertex index
};

struct EdgePoint {
  int lo, hi;
  double t;
  std::size_t point;
  bool operator<(const EdgePoint& o) const { return std::tie(lo, hi, t, point) < std::tie(o.lo, o.hi, o.t, o.point); }
};

// Lawson's flips until every side shared by two triangles is locally
// Delaunay: the constrained Delaunay triangulation of the face's points,
// whose outline (the face's sides, split by their points) never flips.
// `sides` holds per vertex a bit per face side it lies on (two for a
// corner): a flip never joins two vertices of one side, since points sit
// where they really are, a little off the side, and such a chord could
// also be made by the face on the side's other side (a third face on it).
// Edges wait on a stack and a flip queues only the quad's four sides, so
// the work follows the flips, not rounds over every triangle (a face takes
// up to a few hundred points).
void flipToDelaunay(const std::vector<Vector2d>& xy, const std::vector<std::uint8_t>& sides,
                    std::vector<std::array<int, 3>>& tris, double scale) {
  const double tolerance = 1e-12 * scale * scale * scale * scale;
  const std::size_t v_count = xy.size();
  // The triangle holding each directed edge u -> v, or -1.
  std::vector<int> holder(v_count * v_count, -1);
  auto at = [&](int u, int v) -> int& { return holder[static_cast<std::size_t>(u) * v_count + static_cast<std::size_t>(v)]; };
  std::vector<std::pair<int, int>> stack;
  stack.reserve(3 * tris.size());
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int u = tris[t][k], v = tris[t][(k + 1) % 3];
      at(u, v) = static_cast<int>(t);
      stack.emplace_back(u, v);
    }
  // Delaunay flips terminate; the bound only guards against rounding.
  std::size_t flips_left = 4 * tris.size() * tris.size() + 64;
  auto third = [](const std::array<int, 3>& t, int u, int v) {
    for (int k = 0; k < 3; ++k)
      if (t[k] != u && t[k] != v) return t[k];
    return -1;
  };
  while (!stack.empty() && flips_left > 0) {
    const auto [u, v] = stack.back();
    stack.pop_back();
    const int a = at(u, v), b = at(v, u);
    if (a < 0 || b < 0) continue;  // on the outline, or flipped away
    const int w = third(tris[static_cast<std::size_t>(a)], u, v), z = third(tris[static_cast<std::size_t>(b)], u, v);
    // In-circle test of z against the counter-clockwise (u, v, w).
    const Vector2d pu = xy[u] - xy[z], pv = xy[v] - xy[z], pw = xy[w] - xy[z];
    const double det =
        pu.squaredNorm() * cross2(pv, pw) - pv.squaredNorm() * cross2(pu, pw) + pw.squaredNorm() * cross2(pu, pv);
    if (!(det > tolerance) || (sides[w] & sides[z]) != 0) continue;
    // Only a strictly convex quad (u, z, v, w) can take the other diagonal.
    if (!(orient(xy[u], xy[z], xy[w]) > 0.0 && orient(xy[z], xy[v], xy[w]) > 0.0)) continue;
    tris[static_cast<std::size_t>(a)] = {u, z, w};
    tris[static_cast<std::size_t>(b)] = {z, v, w};
    at(u, v) = at(v, u) = -1;
    at(u, z) = at(z, w) = at(w, u) = a;
    at(z, v) = at(v, w) = at(w, z) = b;
    stack.emplace_back(u, z);
    stack.emplace_back(z, v);
    stack.emplace_back(v, w);
    stack.emplace_back(w, u);
    --flips_left;
  }
}

}  // namespace

PointInsertionReport insertPointsIntoMesh(TriangleMesh& mesh, const std::vector<std::size_t>& candidates,
                                          const PointInsertionParameters& params) {
  PointInsertionReport report;
  const std::vector<Vector3d>& positions = mesh.vertices.positions;
  const std::vector<Vector3d>& normals = mesh.vertices.normals;
  std::vector<Triangle>& faces = mesh.faces;
  if (candidates.empty() || faces.empty() || !(params.max_offset > 0.0) || !(params.min_separation > 0.0))
    return report;
  const double sep = params.min_separation;

  // The used vertices, for the nearest-vertex queries, and their faces.
  const std::vector<std::uint8_t> used = referencedVertices(mesh);
  std::vector<int> used_ids;
  std::vector<Vector3d> used_positions;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) {
      used_ids.push_back(static_cast<int>(v));
      used_positions.push_back(positions[v]);
    }
  const VertexFaces vertex_faces = vertexFaces(mesh);

  std::vector<FaceFrame> frames(faces.size());
  tbb::parallel_for(std::size_t{0}, faces.size(), [&](std::size_t f) { frames[f] = frameOf(positions, faces[f]); });

  // An edge may take points only when every face on it can be split there,
  // or the mesh would get a crack.
  std::vector<std::tuple<int, int, int>> edge_faces;  // (lo, hi, face)
  edge_faces.reserve(3 * faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = faces[f][k], b = faces[f][(k + 1) % 3];
      edge_faces.emplace_back(std::min(a, b), std::max(a, b), static_cast<int>(f));
    }
  std::sort(edge_faces.begin(), edge_faces.end());
  auto edgeSplittable = [&](int lo, int hi) {
    auto it = std::lower_bound(edge_faces.begin(), edge_faces.end(), std::make_tuple(lo, hi, -1));
    std::size_t count = 0;
    for (; it != edge_faces.end() && std::get<0>(*it) == lo && std::get<1>(*it) == hi; ++it, ++count)
      if (!frames[std::get<2>(*it)].valid) return false;
    return count == 1 || count == 2;
  };

  // Each candidate's face: of the faces around its nearest used vertices,
  // the one whose plane is nearest among those it projects into (or onto
  // whose sides it falls within the separation) with an agreeing normal.
  const KdTree tree(used_positions);
  std::vector<Placement> placement(candidates.size());
  tbb::parallel_for(std::size_t{0}, candidates.size(), [&](std::size_t c) {
    const std::size_t q = candidates[c];
    const Vector3d& p = positions[q];
    double best_offset = std::numeric_limits<double>::infinity();
    Placement best;
    for (const Neighbour& nb : tree.nearest(p, 8)) {
      const auto v = static_cast<std::size_t>(used_ids[nb.index]);
      for (const int* face = vertex_faces.begin(v); face != vertex_faces.end(v); ++face) {
        const int f = *face;
        const FaceFrame& frame = frames[f];
        if (!frame.valid || normals[q].dot(frame.normal) <= 0.0) continue;
        const double offset = std::abs((p - frame.origin).dot(frame.normal));
        if (offset > params.max_offset || offset > best_offset || (offset == best_offset && f >= best.face)) continue;
        const Vector2d xy = frame.project(p);
        const std::array<double, 3> d = sideDistances(frame.corner, xy);
        if (std::min({d[0], d[1], d[2]}) < -sep) continue;
        best_offset = offset;
        best.face = f;
        best.xy = xy;
      }
    }
    if (best.face < 0) return;
    const FaceFrame& frame = frames[best.face];
    for (const Vector2d& corner : frame.corner)
      if ((corner - best.xy).norm() < sep) return;
    const std::array<double, 3> d = sideDistances(frame.corner, best.xy);
    const int side = static_cast<int>(std::min_element(d.begin(), d.end()) - d.begin());
    if (d[side] < kEdgeBand * sep) {
      const Triangle& f = faces[best.face];
      const int a = f[side], b = f[(side + 1) % 3];
      const int lo = std::min(a, b), hi = std::max(a, b);
      const Vector3d edge = positions[hi] - positions[lo];
      const double length = edge.norm();
      const double t = (p - positions[lo]).dot(edge) / (length * length);
      if (t * length < sep || (1.0 - t) * length < sep) return;
      best.side = side;
      best.t = t;
    }
    placement[c] = best;
  });

  // Points onto edges, in order along each edge, each at least the
  // separation from the last one kept.
  std::vector<EdgePoint> edge_points;
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    const Placement& pl = placement[c];
    if (pl.face < 0 || pl.side < 0) continue;
    const Triangle& f = faces[pl.face];
    const int a = f[pl.side], b = f[(pl.side + 1) % 3];
    edge_points.push_back({std::min(a, b), std::max(a, b), pl.t, candidates[c]});
  }
  std::sort(edge_points.begin(), edge_points.end());
  std::vector<EdgePoint> kept_edge_points;
  for (std::size_t i = 0; i < edge_points.size();) {
    std::size_t j = i;
    while (j < edge_points.size() && edge_points[j].lo == edge_points[i].lo && edge_points[j].hi == edge_points[i].hi)
      ++j;
    if (edgeSplittable(edge_points[i].lo, edge_points[i].hi)) {
      const double length = (positions[edge_points[i].hi] - positions[edge_points[i].lo]).norm();
      double last = 0.0;
      for (std::size_t k = i; k < j; ++k)
        if ((edge_points[k].t - last) * length >= sep) {
          kept_edge_points.push_back(edge_points[k]);
          last = edge_points[k].t;
        }
    }
    i = j;
  }
  auto edgeRange = [&](int lo, int hi) {
    const auto first = std::lower_bound(
        kept_edge_points.begin(), kept_edge_points.end(), std::make_pair(lo, hi),
        [](const EdgePoint& e, const std::pair<int, int>& key) { return std::make_pair(e.lo, e.hi) < key; });
    auto last = first;
    while (last != kept_edge_points.end() && last->lo == lo && last->hi == hi) ++last;
    return std::make_pair(first, last);
  };

  // Inside points per face, by point index.
  std::vector<std::vector<std::size_t>> inside(faces.size());
  for (std::size_t c = 0; c < candidates.size(); ++c)
    if (placement[c].face >= 0 && placement[c].side < 0) inside[placement[c].face].push_back(c);

  // Every face with points is triangulated anew over its corners, its
  // sides' points and its inside points, all where they really are
  // (projected into the face's plane). A new triangle must face the way
  // its points' normals do, as every ball-pivoting face does; where one
  // cannot, the inside point to blame stays out (the face is redone at
  // once), or the edge point to blame does, and both faces on that edge
  // are redone in the next round.
  std::vector<std::uint8_t> edge_active(kept_edge_points.size(), 1);
  struct FaceResult {
    std::vector<Triangle> triangles;  // empty: the face stays as it is
    long failed_edge_point = -1;
    std::size_t inside = 0;
  };
  auto triangulate = [&](std::size_t fi) {
    FaceResult result;
    const Triangle& f = faces[fi];
    const FaceFrame& frame = frames[fi];
    if (!frame.valid) return result;
    const double scale =
        std::max({(frame.corner[1] - frame.corner[0]).norm(), (frame.corner[2] - frame.corner[0]).norm(),
                  (frame.corner[2] - frame.corner[1]).norm()});
    const double min_area = 1e-12 * scale * scale;
    const double far_sq = sep * sep * (1.0 + 1e-9);
    const double clearance_far_sq = kOutlineClearance * kOutlineClearance * sep * sep * (1.0 + 1e-9);
    std::vector<std::uint8_t> inside_off(inside[fi].size(), 0);
    std::vector<Vector2d> xy;
    std::vector<int> global;
    std::vector<long> origin;                      // per local vertex: -1 corner, edge point id, or -(2 + inside slot)
    std::vector<std::uint8_t> sides;               // per local vertex: bit k = on side k (corner k: sides k and k - 1)
    std::vector<std::array<Vector2d, 2>> outline;  // the sides' pieces between their points
    std::vector<std::array<int, 3>> tris;
    for (std::size_t attempt = 0;; ++attempt) {
      xy.assign(frame.corner.begin(), frame.corner.end());
      global = {f[0], f[1], f[2]};
      origin.assign(3, -1);
      sides = {0b101, 0b011, 0b110};
      outline.clear();
      tris = {{0, 1, 2}};
      std::size_t points = 0;
      for (int side = 0; side < 3; ++side) {
        const int a = f[side], b = f[(side + 1) % 3];
        auto [first, last] = edgeRange(std::min(a, b), std::max(a, b));
        std::vector<long> along;
        for (auto it = first; it != last; ++it)
          if (edge_active[static_cast<std::size_t>(it - kept_edge_points.begin())])
            along.push_back(it - kept_edge_points.begin());
        if (a > b) std::reverse(along.begin(), along.end());
        // Split the triangle on the side's remaining piece (prev -> end)
        // at each point in turn, joining it to that triangle's third corner.
        int prev = side;
        const int end = (side + 1) % 3;
        for (long e : along) {
          const int v = static_cast<int>(xy.size());
          xy.push_back(frame.project(positions[kept_edge_points[static_cast<std::size_t>(e)].point]));
          global.push_back(static_cast<int>(kept_edge_points[static_cast<std::size_t>(e)].point));
          origin.push_back(e);
          sides.push_back(static_cast<std::uint8_t>(1u << side));
          std::size_t t = 0;
          int k = 0;
          for (; t < tris.size(); ++t) {
            for (k = 0; k < 3 && !(tris[t][k] == prev && tris[t][(k + 1) % 3] == end); ++k) {
            }
            if (k < 3) break;
          }
          if (t == tris.size()) {  // cannot happen (each split keeps prev -> end); never read past the end
            result.failed_edge_point = e;
            return result;
          }
          const int w = tris[t][(k + 2) % 3];
          if (!(orient(xy[prev], xy[v], xy[w]) > min_area && orient(xy[v], xy[end], xy[w]) > min_area)) {
            result.failed_edge_point = e;
            return result;
          }
          tris[t] = {prev, v, w};
          tris.push_back({v, end, w});
          outline.push_back({xy[prev], xy[v]});
          prev = v;
          ++points;
        }
        outline.push_back({xy[prev], xy[end]});
      }
      std::size_t inserted = 0;
      // A face that keeps failing (a dense clump against a folded side)
      // is bounded in time: after so many attempts it takes no inside point.
      for (std::size_t slot = 0; slot < inside[fi].size() && attempt < kMaxAttempts; ++slot) {
        if (inside_off[slot]) continue;
        if (points >= params.max_points_per_face) break;
        const Vector2d& x = placement[inside[fi][slot]].xy;
        bool crowded = false;
        // Squared distances clearly beyond the bound skip the square root;
        // the comparison itself is the one on lengths.
        for (std::size_t v = 3; v < xy.size() && !crowded; ++v) {
          const double sq = (xy[v] - x).squaredNorm();
          crowded = sq < far_sq && std::sqrt(sq) < sep;
        }
        // A side point a little inside the face must not leave a needle
        // between it, the side and x: x keeps a tenth of a separation from
        // the outline as it really is.
        for (std::size_t k = 0; k < outline.size() && !crowded; ++k) {
          const Vector2d d = outline[k][1] - outline[k][0];
          const double along = std::clamp((x - outline[k][0]).dot(d) / d.squaredNorm(), 0.0, 1.0);
          const double sq = (outline[k][0] + along * d - x).squaredNorm();
          crowded = sq < clearance_far_sq && std::sqrt(sq) < kOutlineClearance * sep;
        }
        if (crowded) continue;
        // The triangle that holds x most deeply; a point on one of its
        // sides (to rounding) would make a flat triangle and stays out.
        // Only a triangle with x on the inner side of all three sides can
        // hold it that deeply (the side distances are these orientations
        // over the sides' lengths), so the others cost no square root.
        std::size_t host = tris.size();
        double depth = -std::numeric_limits<double>::infinity();
        for (std::size_t t = 0; t < tris.size(); ++t) {
          const Vector2d& a = xy[tris[t][0]];
          const Vector2d& b = xy[tris[t][1]];
          const Vector2d& c = xy[tris[t][2]];
          if (!(orient(a, b, x) > 0.0 && orient(b, c, x) > 0.0 && orient(c, a, x) > 0.0)) continue;
          const std::array<Vector2d, 3> corners{a, b, c};
          const std::array<double, 3> d = sideDistances(corners, x);
          const double m = std::min({d[0], d[1], d[2]});
          if (m > depth) {
            depth = m;
            host = t;
          }
        }
        if (!(depth > 1e-3 * sep)) continue;
        const int v = static_cast<int>(xy.size());
        xy.push_back(x);
        global.push_back(static_cast<int>(candidates[inside[fi][slot]]));
        origin.push_back(-2 - static_cast<long>(slot));
        sides.push_back(0);
        const std::array<int, 3> t = tris[host];
        tris[host] = {t[0], t[1], v};
        tris.push_back({t[1], t[2], v});
        tris.push_back({t[2], t[0], v});
        ++inserted;
        ++points;
      }
      if (points == 0) return result;
      flipToDelaunay(xy, sides, tris, scale);
      // The first triangle that is flat in the plane or turned against its
      // points' normals, if any.
      long blamed = -1;
      for (const auto& t : tris) {
        const Vector3d& pa = positions[global[t[0]]];
        const Vector3d fn = (positions[global[t[1]]] - pa).cross(positions[global[t[2]]] - pa);
        Vector3d n_sum = Vector3d::Zero();
        for (int k = 0; k < 3; ++k) n_sum += normals[global[t[k]]].normalized();
        if (orient(xy[t[0]], xy[t[1]], xy[t[2]]) > min_area && fn.dot(n_sum) > 0.0) continue;
        // Blame the inside point with the largest index (it costs this face
        // alone), else the edge point with the largest index.
        long inside_vertex = -1, edge_vertex = -1;
        for (int k = 0; k < 3; ++k) {
          const long o = origin[t[k]];
          if (o <= -2 && (inside_vertex < 0 || global[t[k]] > global[inside_vertex])) inside_vertex = t[k];
          if (o >= 0 && (edge_vertex < 0 || global[t[k]] > global[edge_vertex])) edge_vertex = t[k];
        }
        blamed = inside_vertex >= 0 ? inside_vertex : edge_vertex;
        if (blamed >= 0) break;
      }
      if (blamed < 0) break;
      const long o = origin[static_cast<std::size_t>(blamed)];
      if (o >= 0) {
        result.failed_edge_point = o;
        return result;
      }
      inside_off[static_cast<std::size_t>(-2 - o)] = 1;
    }
    result.inside = 0;
    for (long o : origin) result.inside += o <= -2;
    result.triangles.reserve(tris.size());
    for (const auto& t : tris) result.triangles.emplace_back(global[t[0]], global[t[1]], global[t[2]]);
    return result;
  };

  std::vector<FaceResult> results(faces.size());
  std::vector<std::size_t> dirty;
  for (std::size_t fi = 0; fi < faces.size(); ++fi) {
    bool has_points = !inside[fi].empty();
    for (int side = 0; side < 3 && !has_points; ++side) {
      const int a = faces[fi][side], b = faces[fi][(side + 1) % 3];
      auto [first, last] = edgeRange(std::min(a, b), std::max(a, b));
      has_points = first != last;
    }
    if (has_points) dirty.push_back(fi);
  }
  while (!dirty.empty()) {
    tbb::parallel_for(std::size_t{0}, dirty.size(), [&](std::size_t i) { results[dirty[i]] = triangulate(dirty[i]); });
    std::vector<long> failed;
    for (std::size_t fi : dirty)
      if (results[fi].failed_edge_point >= 0) failed.push_back(results[fi].failed_edge_point);
    std::sort(failed.begin(), failed.end());
    failed.erase(std::unique(failed.begin(), failed.end()), failed.end());
    std::vector<std::size_t> next;
    for (long e : failed) {
      edge_active[static_cast<std::size_t>(e)] = 0;
      const EdgePoint& point = kept_edge_points[static_cast<std::size_t>(e)];
      for (auto it = std::lower_bound(edge_faces.begin(), edge_faces.end(), std::make_tuple(point.lo, point.hi, -1));
           it != edge_faces.end() && std::get<0>(*it) == point.lo && std::get<1>(*it) == point.hi; ++it)
        next.push_back(static_cast<std::size_t>(std::get<2>(*it)));
    }
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    dirty = std::move(next);
  }

  std::vector<Triangle> out;
  out.reserve(faces.size() + 2 * candidates.size());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (results[f].triangles.empty()) {
      out.push_back(faces[f]);
    } else {
      out.insert(out.end(), results[f].triangles.begin(), results[f].triangles.end());
      report.inserted += results[f].inside;
    }
  }
  report.onto_edges = static_cast<std::size_t>(std::count(edge_active.begin(), edge_active.end(), 1));
  report.inserted += report.onto_edges;
  report.left_out = candidates.size() - report.inserted;
  faces = std::move(out);
  return report;
}

}  // namespace icrkit::reconstruction
