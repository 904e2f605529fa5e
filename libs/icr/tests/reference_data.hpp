#pragma once
// The reference ICR library's data (../shared/data/icr-reference, README
// there) as the parity tests read it: settings from file names, meshes as
// the reference read them, and region comparisons.

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/icr/contact_model.hpp>

#include <algorithm>
#include <filesystem>
#include <iterator>
#include <regex>
#include <string>
#include <vector>

namespace icrkit::test {

inline const std::filesystem::path kReferenceDir = std::filesystem::path(ICRKIT_SHARED_DATA_DIR) / "icr-reference";
inline const std::filesystem::path kModelDir = std::filesystem::path(ICRKIT_SHARED_DATA_DIR) / "icr-models";

struct ReferenceSetting {
  std::string model;
  icr::ContactModel contact_model;
  std::size_t fingers = 0;
  double alpha = 0.0;
};

// "Fish_5k__frictional_mu0.8_L8_f4_a0.5.json" -> model Fish_5k, frictional,
// mu 0.8, L 8, 4 fingers, alpha 0.5; a patch file ("..._patch5mm.json")
// reads the same (its patch is in the file's "patch" object).
inline bool parseReferenceSetting(const std::string& name, ReferenceSetting& s) {
  static const std::regex pattern(
      R"(^(.+)__(frictional|softfinger|frictionless)(?:_mu([0-9.]+))?(?:_muT([0-9.]+))?(?:_L([0-9]+))?_f([0-9]+)_a([0-9.]+)(?:_patch[0-9.]+mm)?\.json$)");
  std::smatch m;
  if (!std::regex_match(name, m, pattern)) return false;
  s.model = m[1];
  const std::string type = m[2];
  s.contact_model.type = type == "frictional"   ? icr::ContactType::Frictional
                         : type == "softfinger" ? icr::ContactType::SoftFinger
                                                : icr::ContactType::Frictionless;
  if (m[3].matched) s.contact_model.friction = std::stod(m[3]);
  if (m[4].matched) s.contact_model.torsional_friction = std::stod(m[4]);
  if (m[5].matched) s.contact_model.cone_edges = std::stoi(m[5]);
  s.fingers = std::stoul(m[6]);
  s.alpha = std::stod(m[7]);
  return true;
}

// The reference library read coordinates and normals in single precision.
inline TriangleMesh readReferenceMesh(const std::string& model) {
  TriangleMesh mesh = io::readTriangleMesh((kModelDir / (model + ".obj")).string());
  for (auto& p : mesh.vertices.positions) p = p.cast<float>().cast<double>();
  for (auto& n : mesh.vertices.normals) n = n.cast<float>().cast<double>();
  return mesh;
}

inline std::size_t symmetricDifference(const std::vector<int>& a, const std::vector<int>& b) {
  std::vector<int> d;
  std::set_symmetric_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(d));
  return d.size();
}

inline std::size_t unionSize(const std::vector<int>& a, const std::vector<int>& b) {
  std::vector<int> u;
  std::set_union(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(u));
  return u.size();
}

}  // namespace icrkit::test
