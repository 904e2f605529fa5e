#pragma once
/// \file
/// The regions file: the JSON summary `icrkit icr` writes next to its PLY,
/// read back by `icrkit render` and by anyone scripting around the command.
/// Only its "regions" array belongs to this format:
///
///     {"regions": [{"finger": 0, "contact": 812, "vertices": [803, 812, ...],
///                   "area_m2": 1.2e-05,
///                   "recommended": {"vertex": 812, "depth_m": 0.0021}}, ...], ...}
///
/// `finger` defaults to the entry's position and `contact` to none; vertex
/// indices are 0-based indices of the mesh the regions were grown on.

#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/icr/independent_contact_regions.hpp>

#include <string>
#include <vector>

namespace icrkit::icr {

/// One region as a regions file holds it.
struct StoredRegion {
  int finger = 0;
  int contact = -1;           ///< -1 when the entry names none
  std::vector<int> vertices;  ///< as stored (the writer stores them sorted)
};

/// The "regions" array of `regions` as JSON text (compact, keys sorted, so
/// that the same regions always give the same bytes).
std::string regionsJson(const std::vector<ContactRegion>& regions);

/// Parses `text`, a JSON document with a "regions" array, and checks every
/// index against `mesh`: in range and used by a face (no region holds any
/// other vertex). Errors name `source` (the file), the entry and field
/// (`regions[2] (finger 2).vertices[5]`) and `mesh_name`.
std::vector<StoredRegion> parseRegionsJson(const std::string& text, const std::string& source, const TriangleMesh& mesh,
                                           const std::string& mesh_name);
/// Reads the regions file at `path`; as parseRegionsJson.
std::vector<StoredRegion> readRegionsFile(const std::string& path, const TriangleMesh& mesh,
                                          const std::string& mesh_name);

}  // namespace icrkit::icr
