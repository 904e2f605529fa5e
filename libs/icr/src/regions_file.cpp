#include <icrkit/icr/regions_file.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_topology.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <sstream>

namespace icrkit::icr {

std::string regionsJson(const std::vector<ContactRegion>& regions) {
  nlohmann::json array = nlohmann::json::array();
  for (const ContactRegion& region : regions)
    array.push_back({{"finger", region.finger},
                     {"contact", region.contact},
                     {"vertices", region.vertices},
                     {"area_m2", region.area_m2},
                     {"recommended", {{"vertex", region.recommended.vertex}, {"depth_m", region.recommended.depth_m}}}});
  return array.dump();
}

std::vector<StoredRegion> parseRegionsJson(const std::string& text, const std::string& source, const TriangleMesh& mesh,
                                           const std::string& mesh_name) {
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(text);
  } catch (const std::exception& error) {
    throw InputError(source, "", std::string("is not valid JSON: ") + error.what());
  }
  if (!document.is_object() || !document.contains("regions") || !document["regions"].is_array())
    throw InputError(source, "", "has no \"regions\" array; expected the JSON summary `icrkit icr` writes next to its PLY");
  const long long count = static_cast<long long>(mesh.vertexCount());
  const std::vector<std::uint8_t> referenced = referencedVertices(mesh);
  auto vertexIndex = [&](const nlohmann::json& value, const std::string& where) {
    if (!value.is_number_integer()) throw InputError(source, where, "expected a vertex index, got " + value.dump());
    const long long v = value.get<long long>();
    if (v < 0 || v >= count)
      throw InputError(source, where,
                       "vertex " + std::to_string(v) + " is out of range for " + mesh_name + " (" +
                           std::to_string(count) + " vertices); were the regions computed on another mesh?");
    // Region growth never puts such a vertex in a region or makes it a contact.
    if (!referenced[static_cast<std::size_t>(v)])
      throw InputError(source, where,
                       "vertex " + std::to_string(v) + " is used by no face of " + mesh_name +
                           ", so it cannot be in a region; were the regions computed on another mesh?");
    return static_cast<int>(v);
  };
  std::vector<StoredRegion> stored;
  const nlohmann::json& regions = document["regions"];
  for (std::size_t r = 0; r < regions.size(); ++r) {
    const nlohmann::json& region = regions[r];
    const std::string where = "regions[" + std::to_string(r) + "]";
    if (!region.is_object() || !region.contains("vertices") || !region["vertices"].is_array())
      throw InputError(source, where, "expected an object with a \"vertices\" array");
    StoredRegion entry;
    entry.finger = static_cast<int>(r);
    if (region.contains("finger")) {
      if (!region["finger"].is_number_integer() || region["finger"].get<long long>() < 0 ||
          region["finger"].get<long long>() > 1000)
        throw InputError(source, where + ".finger", "expected a finger index 0..1000, got " + region["finger"].dump());
      entry.finger = region["finger"].get<int>();
    }
    const bool repeated = std::any_of(stored.begin(), stored.end(),
                                      [&](const StoredRegion& other) { return other.finger == entry.finger; });
    if (repeated) throw InputError(source, where, "finger " + std::to_string(entry.finger) + " has more than one region");
    const std::string named = where + " (finger " + std::to_string(entry.finger) + ")";
    if (region.contains("contact")) entry.contact = vertexIndex(region["contact"], named + ".contact");
    const nlohmann::json& list = region["vertices"];
    for (std::size_t k = 0; k < list.size(); ++k)
      entry.vertices.push_back(vertexIndex(list[k], named + ".vertices[" + std::to_string(k) + "]"));
    stored.push_back(std::move(entry));
  }
  return stored;
}

std::vector<StoredRegion> readRegionsFile(const std::string& path, const TriangleMesh& mesh,
                                          const std::string& mesh_name) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "", "cannot be read; expected the JSON summary `icrkit icr` writes next to its PLY");
  std::ostringstream text;
  text << in.rdbuf();
  return parseRegionsJson(text.str(), path, mesh, mesh_name);
}

}  // namespace icrkit::icr
