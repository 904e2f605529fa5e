#include <icrkit/icr/region_mesh.hpp>

#include <icrkit/core/error.hpp>

#include <array>
#include <string>

namespace icrkit::icr {
namespace {

// Tableau 10 without its grey, which marks vertices in no region: distinct
// hues that stay apart for the usual 3-5 fingers.
constexpr std::array<Colour, 9> kPalette{{{31, 119, 180},
                                          {255, 127, 14},
                                          {44, 160, 44},
                                          {214, 39, 40},
                                          {148, 103, 189},
                                          {140, 86, 75},
                                          {227, 119, 194},
                                          {188, 189, 34},
                                          {23, 190, 207}}};
constexpr Colour kNoRegion{190, 190, 190};
constexpr Colour kRecommended{0, 0, 0};

}  // namespace

TriangleMesh regionMesh(const TriangleMesh& mesh, const std::vector<ContactRegion>& regions) {
  const std::size_t n = mesh.vertexCount();
  for (const ContactRegion& r : regions) {
    for (int v : r.vertices)
      if (v < 0 || static_cast<std::size_t>(v) >= n)
        throw InputError(
            "regions", "finger " + std::to_string(r.finger),
            "vertex " + std::to_string(v) + " is not a vertex of the mesh (" + std::to_string(n) + " vertices)");
    if (r.recommended.vertex >= 0 && static_cast<std::size_t>(r.recommended.vertex) >= n)
      throw InputError("regions", "finger " + std::to_string(r.finger),
                       "recommended vertex " + std::to_string(r.recommended.vertex) + " is not a vertex of the mesh");
  }
  TriangleMesh out = mesh;
  std::vector<double> region(n, -1.0);
  // Later fingers first, so that a vertex in several regions ends up with
  // the lowest finger index.
  for (auto it = regions.rbegin(); it != regions.rend(); ++it)
    for (int v : it->vertices) region[static_cast<std::size_t>(v)] = static_cast<double>(it->finger);
  out.vertices.colours.assign(n, kNoRegion);
  for (std::size_t v = 0; v < n; ++v)
    if (region[v] >= 0) out.vertices.colours[v] = kPalette[static_cast<std::size_t>(region[v]) % kPalette.size()];
  out.vertices.attributes.add("region", ScalarType::Int32, std::move(region));
  std::vector<double> recommended(n, -1.0);
  for (auto it = regions.rbegin(); it != regions.rend(); ++it)
    if (it->recommended.vertex >= 0) {
      recommended[static_cast<std::size_t>(it->recommended.vertex)] = static_cast<double>(it->finger);
      out.vertices.colours[static_cast<std::size_t>(it->recommended.vertex)] = kRecommended;
    }
  out.vertices.attributes.add("recommended", ScalarType::Int32, std::move(recommended));
  return out;
}

}  // namespace icrkit::icr
