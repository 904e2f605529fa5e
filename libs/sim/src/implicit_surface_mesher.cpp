#include "implicit_surface_mesher.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace icrkit::sim {

SampleGrid gridAround(const Eigen::AlignedBox3d& bounds, double cell, const Eigen::Vector3d& anchor,
                      int margin_cells) {
  if (!(cell > 0.0) || !std::isfinite(cell)) throw std::invalid_argument("gridAround: the cell size must be > 0");
  if (bounds.isEmpty()) throw std::invalid_argument("gridAround: empty bounds");
  SampleGrid grid;
  grid.cell = cell;
  for (int a = 0; a < 3; ++a) {
    const double first = std::floor((bounds.min()[a] - anchor[a]) / cell) - margin_cells;
    const double last = std::ceil((bounds.max()[a] - anchor[a]) / cell) + margin_cells;
    grid.origin[a] = anchor[a] + first * cell;
    grid.nodes[a] = static_cast<int>(last - first) + 1;
  }
  return grid;
}

namespace {

// Corner c of a cube sits at offset (c & 1, (c >> 1) & 1, (c >> 2) & 1)
// cells from the cube's first node. The six faces with their corners
// counter-clockwise seen from outside the cube: consecutive faces then run
// a shared cube edge in opposite directions.
constexpr int kFaceCorners[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};

// The twelve cube edges, numbered axis * 4 + (the lower corner's bits on the
// two other axes).
struct CubeEdges {
  std::array<int, 12> lower_corner{};
  std::array<int, 12> axis{};
  // Two edges lie on a common cube face: a diagonal between their vertices
  // could then also be a side or diagonal in the neighbouring cube.
  std::array<std::array<bool, 12>, 12> share_face{};

  CubeEdges() {
    for (int a = 0; a < 3; ++a)
      for (int o = 0; o < 4; ++o) {
        int corner = 0, bit = 0;
        for (int b = 0; b < 3; ++b)
          if (b != a) corner |= ((o >> bit++) & 1) << b;
        lower_corner[a * 4 + o] = corner;
        axis[a * 4 + o] = a;
      }
    for (int e = 0; e < 12; ++e)
      for (int g = 0; g < 12; ++g) {
        bool share = false;
        for (int c = 0; c < 3; ++c)
          if (c != axis[e] && c != axis[g] && ((lower_corner[e] >> c) & 1) == ((lower_corner[g] >> c) & 1))
            share = true;
        share_face[e][g] = share;
      }
  }

  static int between(int a, int b) {
    const int lower = a & b, diff = a ^ b;
    const int ax = diff == 1 ? 0 : diff == 2 ? 1 : 2;
    int o = 0, bit = 0;
    for (int c = 0; c < 3; ++c)
      if (c != ax) o |= ((lower >> c) & 1) << bit++;
    return ax * 4 + o;
  }
};

const CubeEdges& cubeEdges() {
  static const CubeEdges edges;  // immutable after its thread-safe construction
  return edges;
}

// The zero of the field on the segment p0-p1 whose end values differ in
// sign, by false position with the Illinois modification (superlinear, and
// it never leaves the bracket even where CSG makes the field kinked).
Eigen::Vector3d rootOnEdge(const ScalarField& field, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, double f0,
                           double f1, double tolerance) {
  double a = 0.0, b = 1.0, fa = f0, fb = f1;
  double t = fa / (fa - fb);
  int kept = 0;  // which end survived the last step: -1 = a, +1 = b
  for (int iteration = 0; iteration < 24; ++iteration) {
    t = (a * fb - b * fa) / (fb - fa);
    const double ft = field(p0 + t * (p1 - p0));
    if (std::abs(ft) <= tolerance || b - a <= 1e-9) break;
    if ((ft < 0.0) == (fb < 0.0)) {
      b = t;
      fb = ft;
      if (kept == -1) fa *= 0.5;
      kept = -1;
    } else {
      a = t;
      fa = ft;
      if (kept == 1) fb *= 0.5;
      kept = 1;
    }
  }
  // A vertex right at a node would make the faces around that node
  // degenerate; 1 % of a cell is far below the surface's chord error.
  t = std::clamp(t, 0.01, 0.99);
  return p0 + t * (p1 - p0);
}

// Newton steps towards the level set along the field's gradient (central
// differences), each at most a quarter cell and in all at most half a cell
// from the start, so a vertex cannot run off across a thin part.
Eigen::Vector3d projectOntoLevelSet(const ScalarField& field, const Eigen::Vector3d& start, double cell) {
  const double h = 1e-4 * cell;
  Eigen::Vector3d p = start;
  for (int iteration = 0; iteration < 6; ++iteration) {
    const double f = field(p);
    if (std::abs(f) <= 1e-7 * cell) break;
    Eigen::Vector3d g;
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e[a] = h;
      g[a] = (field(p + e) - field(p - e)) / (2.0 * h);
    }
    const double g2 = g.squaredNorm();
    if (!(g2 > 1e-12)) break;
    Eigen::Vector3d step = f * g / g2;
    const double length = step.norm();
    if (length > 0.25 * cell) step *= 0.25 * cell / length;
    p -= step;
    const Eigen::Vector3d moved = p - start;
    if (moved.norm() > 0.5 * cell) {
      p = start + moved * (0.5 * cell / moved.norm());
      break;
    }
  }
  return p;
}

}  // namespace

TriangleMesh meshImplicitSurface(const ScalarField& field, const SampleGrid& grid, ImplicitMeshStatistics* statistics) {
  const int nx = grid.nodes.x(), ny = grid.nodes.y(), nz = grid.nodes.z();
  if (nx < 2 || ny < 2 || nz < 2) throw std::invalid_argument("meshImplicitSurface: at least 2 nodes per axis");
  if (!(grid.cell > 0.0) || !std::isfinite(grid.cell))
    throw std::invalid_argument("meshImplicitSurface: the cell size must be > 0");
  const std::size_t sy = static_cast<std::size_t>(nx), sz = sy * static_cast<std::size_t>(ny);
  const std::size_t node_count = sz * static_cast<std::size_t>(nz);
  const std::size_t stride[3] = {1, sy, sz};
  auto index = [&](int i, int j, int k) { return static_cast<std::size_t>(k) * sz + static_cast<std::size_t>(j) * sy + i; };

  // Sampling dominates for a cheap field on a fine grid; slices are independent.
  std::vector<double> value(node_count);
  tbb::parallel_for(tbb::blocked_range<int>(0, nz), [&](const tbb::blocked_range<int>& range) {
    for (int k = range.begin(); k != range.end(); ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) value[index(i, j, k)] = field(grid.node(i, j, k));
  });
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double v = value[index(i, j, k)];
        if (!std::isfinite(v)) throw std::invalid_argument("meshImplicitSurface: non-finite field value");
        const bool boundary = i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1;
        if (boundary && v < 0.0)
          throw std::invalid_argument("meshImplicitSurface: the solid reaches the grid boundary (node " +
                                      std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) + ")");
      }
  auto inside = [&](std::size_t n) { return value[n] < 0.0; };

  // One vertex per grid edge that changes sign, numbered in node order.
  std::vector<int> edge_vertex(3 * node_count, -1);
  std::vector<std::pair<std::size_t, int>> crossings;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const std::size_t n = index(i, j, k);
        const int limit[3] = {nx, ny, nz}, at[3] = {i, j, k};
        for (int a = 0; a < 3; ++a)
          if (at[a] + 1 < limit[a] && inside(n) != inside(n + stride[a])) {
            edge_vertex[3 * n + a] = static_cast<int>(crossings.size());
            crossings.emplace_back(n, a);
          }
      }
  std::vector<Eigen::Vector3d> positions(crossings.size());
  const double tolerance = 1e-7 * grid.cell;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, crossings.size(), 1024),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t v = range.begin(); v != range.end(); ++v) {
                        const auto [n, a] = crossings[v];
                        const int i = static_cast<int>(n % sy), j = static_cast<int>((n / sy) % ny),
                                  k = static_cast<int>(n / sz);
                        Eigen::Vector3i to(i, j, k);
                        ++to[a];
                        positions[v] = rootOnEdge(field, grid.node(i, j, k), grid.node(to.x(), to.y(), to.z()),
                                                  value[n], value[n + stride[a]], tolerance);
                      }
                    });
  const std::size_t edge_vertices = positions.size();

  const CubeEdges& edges = cubeEdges();
  std::vector<Triangle> faces;
  faces.reserve(2 * positions.size());
  std::size_t loops = 0;
  for (int k = 0; k + 1 < nz; ++k)
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i) {
        const std::size_t n0 = index(i, j, k);
        std::size_t corner[8];
        double f[8];
        int mask = 0;
        for (int c = 0; c < 8; ++c) {
          corner[c] = n0 + (c & 1) * stride[0] + ((c >> 1) & 1) * stride[1] + ((c >> 2) & 1) * stride[2];
          f[c] = value[corner[c]];
          if (f[c] < 0.0) mask |= 1 << c;
        }
        if (mask == 0 || mask == 255) continue;
        auto in = [&](int c) { return ((mask >> c) & 1) != 0; };

        // Segments on the faces, each from the crossing where the face's
        // counter-clockwise boundary leaves the inside to the one where it
        // re-enters: the inside then lies to the left seen from outside.
        int next[12];
        std::fill(next, next + 12, -1);
        for (const auto& q : kFaceCorners) {
          int exits[2], entries[2], ne = 0, nn = 0;
          for (int s = 0; s < 4; ++s) {
            const int a = q[s], b = q[(s + 1) % 4];
            if (in(a) && !in(b)) exits[ne++] = s;
            if (!in(a) && in(b)) entries[nn++] = s;
          }
          if (ne == 0) continue;
          auto edgeOf = [&](int s) { return CubeEdges::between(q[s], q[(s + 1) % 4]); };
          if (ne == 1) {
            next[edgeOf(exits[0])] = edgeOf(entries[0]);
            continue;
          }
          // Ambiguous face: the inside corners are joined through the face
          // centre when the bilinear saddle value is negative, i.e. when the
          // product of the inside values exceeds that of the outside ones.
          // The products are the same numbers in both cubes sharing the face.
          const bool first_in = in(q[0]);
          const double in_product = first_in ? f[q[0]] * f[q[2]] : f[q[1]] * f[q[3]];
          const double out_product = first_in ? f[q[1]] * f[q[3]] : f[q[0]] * f[q[2]];
          const bool joined = in_product > out_product;
          for (int x = 0; x < 2; ++x) {
            const int s = exits[x];
            next[edgeOf(s)] = edgeOf(joined ? (s + 1) % 4 : (s + 3) % 4);
          }
        }

        auto vertexOf = [&](int e) {
          return edge_vertex[3 * corner[edges.lower_corner[e]] + edges.axis[e]];
        };
        bool traced[12] = {};
        for (int e0 = 0; e0 < 12; ++e0) {
          if (next[e0] < 0 || traced[e0]) continue;
          int loop[12], m = 0;
          for (int e = e0; !traced[e]; e = next[e]) {
            traced[e] = true;
            loop[m++] = e;
          }
          ++loops;
          int v[12];
          for (int s = 0; s < m; ++s) v[s] = vertexOf(loop[s]);
          // The loop runs with the inside to its left (seen from outside
          // the cube), i.e. clockwise seen from the outside of the surface:
          // faces take its vertices in reverse.
          if (m == 3) {
            faces.emplace_back(v[0], v[2], v[1]);
            continue;
          }
          int apex = -1;
          double best = std::numeric_limits<double>::infinity();
          for (int a = 0; a < m; ++a) {
            bool safe = true;
            double spread = 0.0;
            for (int t = 2; t + 1 < m && safe; ++t) {
              const int s = (a + t) % m;
              safe = !edges.share_face[loop[a]][loop[s]];
              spread += (positions[v[a]] - positions[v[s]]).squaredNorm();
            }
            if (safe && spread < best) {
              best = spread;
              apex = a;
            }
          }
          if (apex >= 0) {
            for (int t = 1; t + 1 < m; ++t)
              faces.emplace_back(v[apex], v[(apex + t + 1) % m], v[(apex + t) % m]);
            continue;
          }
          Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
          for (int s = 0; s < m; ++s) centroid += positions[v[s]];
          const int c = static_cast<int>(positions.size());
          positions.push_back(centroid / m);
          for (int s = 0; s < m; ++s) faces.emplace_back(c, v[(s + 1) % m], v[s]);
        }
      }

  tbb::parallel_for(tbb::blocked_range<std::size_t>(edge_vertices, positions.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t p = range.begin(); p != range.end(); ++p)
                        positions[p] = projectOntoLevelSet(field, positions[p], grid.cell);
                    });

  if (statistics) {
    statistics->edge_vertices = edge_vertices;
    statistics->centre_vertices = positions.size() - edge_vertices;
    statistics->loops = loops;
  }
  TriangleMesh mesh;
  mesh.vertices.positions = std::move(positions);
  mesh.faces = std::move(faces);
  return mesh;
}

}  // namespace icrkit::sim
