#include <icrkit/eval/finger_intersections.hpp>

#include <icrkit/core/error.hpp>

#include <algorithm>
#include <string>

namespace icrkit::eval {

std::vector<FingerIntersection> intersectByFinger(const IntersectionEstimator& cad, const std::vector<int>& cad_fingers,
                                                  const std::vector<std::vector<int>>& cad_regions,
                                                  const TriangleMesh& scan, const std::vector<int>& scan_fingers,
                                                  const std::vector<std::vector<int>>& scan_regions) {
  if (cad_fingers.size() != cad_regions.size()) throw InputError("CAD regions", "", "expected one finger per region");
  if (scan_fingers.size() != scan_regions.size())
    throw InputError("reconstructed regions", "", "expected one finger per region");
  const auto missing = [](const std::vector<int>& fingers, int finger) {
    return std::find(fingers.begin(), fingers.end(), finger) == fingers.end();
  };
  for (int finger : cad_fingers)
    if (missing(scan_fingers, finger))
      throw InputError("reconstructed regions", "",
                       "has no region for finger " + std::to_string(finger) + ", which the CAD regions have");
  for (int finger : scan_fingers)
    if (missing(cad_fingers, finger))
      throw InputError("CAD regions", "",
                       "has no region for finger " + std::to_string(finger) + ", which the reconstructed regions have");
  std::vector<FingerIntersection> out;
  for (std::size_t r = 0; r < cad_fingers.size(); ++r) {
    FingerIntersection entry;
    entry.finger = cad_fingers[r];
    entry.cad_region = r;
    entry.scan_region = static_cast<std::size_t>(std::find(scan_fingers.begin(), scan_fingers.end(), entry.finger) -
                                                 scan_fingers.begin());
    entry.intersection = cad.estimate(cad_regions[r], scan, scan_regions[entry.scan_region]);
    out.push_back(std::move(entry));
  }
  return out;
}

}  // namespace icrkit::eval
