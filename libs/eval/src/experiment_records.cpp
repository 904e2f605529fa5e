#include <icrkit/eval/experiment_records.hpp>

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <tuple>
#include <utility>

namespace icrkit::eval {
namespace {

// Insertion-ordered so that a line reads in the order of the struct
// (dataset first), which makes grasps.jsonl pleasant to grep and diff.
using Json = nlohmann::ordered_json;

// JSON has no NaN or infinity and nlohmann would silently write null, which
// here already means "unset"; spelling them as strings keeps the round trip
// exact for whatever the runner produces.
Json doubleToJson(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "Infinity" : "-Infinity";
  // nlohmann writes the shortest text that parses back to the same double.
  return value;
}

Json optionalToJson(const std::optional<double>& value) {
  return value ? doubleToJson(*value) : Json(nullptr);
}

Json regionToJson(const RegionComparison& region) {
  Json j;
  j["vertices"] = region.vertices;
  j["area_m2"] = doubleToJson(region.area_m2);
  j["intersection_area_m2"] = doubleToJson(region.intersection_area_m2);
  j["false_positive_area_m2"] = doubleToJson(region.false_positive_area_m2);
  j["intersection_percent"] = optionalToJson(region.intersection_percent);
  j["false_positive_percent"] = optionalToJson(region.false_positive_percent);
  j["d1_m"] = doubleToJson(region.d1_m);
  j["d2_m"] = doubleToJson(region.d2_m);
  j["quality"] = optionalToJson(region.quality);
  if (region.recommended_inside) j["recommended_inside"] = *region.recommended_inside;
  return j;
}

Json regionsToJson(const std::vector<RegionComparison>& regions) {
  Json array = Json::array();
  for (const auto& region : regions) array.push_back(regionToJson(region));
  return array;
}

Json doublesToJson(const std::vector<double>& values) {
  Json array = Json::array();
  for (const double value : values) array.push_back(doubleToJson(value));
  return array;
}

Json snappedToJson(const SnappedOutcome& snapped) {
  Json j;
  j["contacts"] = snapped.contacts;
  j["move_distances_m"] = doublesToJson(snapped.move_distances_m);
  j["task_fulfilled"] = snapped.task_fulfilled;
  j["epsilon"] = doubleToJson(snapped.epsilon);
  j["reason"] = snapped.reason;
  return j;
}

Json picksToJson(const PickCheck& picks) {
  Json j{{"tried", picks.tried}, {"mapped", picks.mapped}, {"held", picks.held}};
  if (picks.aimed_held) j["aimed_held"] = *picks.aimed_held;
  return j;
}

Json meshToJson(const MeshOutcome& mesh) {
  Json j;
  j["contacts"] = mesh.contacts;
  j["preselection_passed"] = mesh.preselection_passed;
  j["task_fulfilled"] = mesh.task_fulfilled;
  j["epsilon"] = doubleToJson(mesh.epsilon);
  j["reason"] = mesh.reason;
  j["regions"] = regionsToJson(mesh.regions);
  // Written only when computed, so records without it (the raw mesh, grasps
  // that passed the preselection, runs before it existed) keep their form.
  if (mesh.snapped) j["snapped"] = snappedToJson(*mesh.snapped);
  if (mesh.picks) j["picks"] = picksToJson(*mesh.picks);
  if (!mesh.conservative.empty()) {
    Json conservative = Json::array();
    for (const ConservativeOutcome& c : mesh.conservative) {
      Json item{{"sigmas", doubleToJson(c.sigmas)}, {"regions", regionsToJson(c.regions)}};
      if (c.picks) item["picks"] = picksToJson(*c.picks);
      conservative.push_back(std::move(item));
    }
    j["conservative"] = std::move(conservative);
  }
  return j;
}

Json patchMeshToJson(const PatchMeshOutcome& mesh) {
  Json j{{"task_fulfilled", mesh.task_fulfilled},
         {"epsilon", doubleToJson(mesh.epsilon)},
         {"reason", mesh.reason},
         {"regions", regionsToJson(mesh.regions)}};
  if (mesh.aimed_held) j["aimed_held"] = *mesh.aimed_held;
  return j;
}

Json patchToJson(const PatchRecord& patch) {
  Json j;
  j["radius_m"] = doubleToJson(patch.radius_m);
  j["filter_border"] = patch.filter_border;
  j["evaluated"] = patch.evaluated;
  j["cad_epsilon"] = doubleToJson(patch.cad_epsilon);
  j["tws_radius"] = doubleToJson(patch.tws_radius);
  j["cad_region_areas_m2"] = doublesToJson(patch.cad_region_areas_m2);
  j["raw"] = patchMeshToJson(patch.raw);
  j["filtered"] = patchMeshToJson(patch.filtered);
  return j;
}

/// Reads fields of one JSON object, throwing InputError that names the line
/// and the dotted path of the offending field.
class FieldReader {
public:
  FieldReader(const std::string& source, std::size_t line) : source_(source), line_(line) {}

  [[noreturn]] void fail(const std::string& field, const std::string& expected) const {
    throw InputError(source_, line_ > 0 ? "line " + std::to_string(line_) : std::string(),
                     field.empty() ? expected : "field \"" + field + "\": " + expected);
  }

  const Json& member(const Json& object, const std::string& path, const char* key) const {
    const std::string field = join(path, key);
    if (!object.is_object()) fail(path, "expected a JSON object");
    auto it = object.find(key);
    if (it == object.end()) fail(field, "missing");
    return *it;
  }

  double number(const Json& object, const std::string& path, const char* key) const {
    return numberValue(member(object, path, key), join(path, key));
  }

  std::optional<double> optionalNumber(const Json& object, const std::string& path, const char* key) const {
    const Json& value = member(object, path, key);
    if (value.is_null()) return std::nullopt;
    return numberValue(value, join(path, key));
  }

  std::size_t count(const Json& object, const std::string& path, const char* key) const {
    const Json& value = member(object, path, key);
    if (!value.is_number_unsigned() && !(value.is_number_integer() && value.get<std::int64_t>() >= 0))
      fail(join(path, key), "expected a non-negative integer");
    return value.get<std::size_t>();
  }

  bool boolean(const Json& object, const std::string& path, const char* key) const {
    const Json& value = member(object, path, key);
    if (!value.is_boolean()) fail(join(path, key), "expected true or false");
    return value.get<bool>();
  }

  std::string string(const Json& object, const std::string& path, const char* key) const {
    const Json& value = member(object, path, key);
    if (!value.is_string()) fail(join(path, key), "expected a string");
    return value.get<std::string>();
  }

  std::vector<int> intArray(const Json& object, const std::string& path, const char* key) const {
    const Json& value = array(object, path, key);
    std::vector<int> result;
    result.reserve(value.size());
    for (std::size_t i = 0; i < value.size(); ++i) {
      const Json& item = value[i];
      if (!fitsInt(item)) fail(indexed(join(path, key), i), "expected an integer vertex index");
      result.push_back(item.get<int>());
    }
    return result;
  }

  std::vector<double> doubleArray(const Json& object, const std::string& path, const char* key) const {
    const Json& value = array(object, path, key);
    std::vector<double> result;
    result.reserve(value.size());
    for (std::size_t i = 0; i < value.size(); ++i) result.push_back(numberValue(value[i], indexed(join(path, key), i)));
    return result;
  }

  /// The member, or null when the key is absent: for fields added after
  /// records were first written.
  const Json& optionalMember(const Json& object, const std::string& path, const char* key) const {
    static const Json absent;
    if (!object.is_object()) fail(path, "expected a JSON object");
    auto it = object.find(key);
    return it == object.end() ? absent : *it;
  }

  const Json& array(const Json& object, const std::string& path, const char* key) const {
    const Json& value = member(object, path, key);
    if (!value.is_array()) fail(join(path, key), "expected an array");
    return value;
  }

  static std::string join(const std::string& path, const char* key) { return path.empty() ? key : path + "." + key; }
  static std::string indexed(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

private:
  static bool fitsInt(const Json& value) {
    if (value.is_number_unsigned()) return value.get<std::uint64_t>() <= std::uint64_t(std::numeric_limits<int>::max());
    if (value.is_number_integer()) {
      const auto v = value.get<std::int64_t>();
      return v >= std::numeric_limits<int>::min() && v <= std::numeric_limits<int>::max();
    }
    return false;
  }

  double numberValue(const Json& value, const std::string& field) const {
    if (value.is_number()) return value.get<double>();
    if (value.is_string()) {
      const auto& text = value.get_ref<const std::string&>();
      if (text == "NaN") return std::numeric_limits<double>::quiet_NaN();
      if (text == "Infinity") return std::numeric_limits<double>::infinity();
      if (text == "-Infinity") return -std::numeric_limits<double>::infinity();
    }
    fail(field, "expected a number");
  }

  const std::string& source_;
  std::size_t line_;
};

RegionComparison regionFromJson(const FieldReader& in, const Json& j, const std::string& path) {
  RegionComparison region;
  region.vertices = in.count(j, path, "vertices");
  region.area_m2 = in.number(j, path, "area_m2");
  region.intersection_area_m2 = in.number(j, path, "intersection_area_m2");
  region.false_positive_area_m2 = in.number(j, path, "false_positive_area_m2");
  region.intersection_percent = in.optionalNumber(j, path, "intersection_percent");
  region.false_positive_percent = in.optionalNumber(j, path, "false_positive_percent");
  region.d1_m = in.number(j, path, "d1_m");
  region.d2_m = in.number(j, path, "d2_m");
  region.quality = in.optionalNumber(j, path, "quality");
  const Json& inside = in.optionalMember(j, path, "recommended_inside");
  if (!inside.is_null()) {
    if (!inside.is_boolean()) in.fail(FieldReader::join(path, "recommended_inside"), "expected true or false");
    region.recommended_inside = inside.get<bool>();
  }
  return region;
}

std::vector<RegionComparison> regionsFromJson(const FieldReader& in, const Json& j, const std::string& path) {
  const Json& regions = in.array(j, path, "regions");
  const std::string regionsPath = FieldReader::join(path, "regions");
  std::vector<RegionComparison> out;
  for (std::size_t i = 0; i < regions.size(); ++i) {
    const std::string regionPath = FieldReader::indexed(regionsPath, i);
    if (!regions[i].is_object()) in.fail(regionPath, "expected a JSON object");
    out.push_back(regionFromJson(in, regions[i], regionPath));
  }
  return out;
}

SnappedOutcome snappedFromJson(const FieldReader& in, const Json& j, const std::string& path) {
  if (!j.is_object()) in.fail(path, "expected a JSON object or null");
  SnappedOutcome snapped;
  snapped.contacts = in.intArray(j, path, "contacts");
  snapped.move_distances_m = in.doubleArray(j, path, "move_distances_m");
  snapped.task_fulfilled = in.boolean(j, path, "task_fulfilled");
  snapped.epsilon = in.number(j, path, "epsilon");
  snapped.reason = in.string(j, path, "reason");
  return snapped;
}

std::optional<PickCheck> picksFromJson(const FieldReader& in, const Json& j, const std::string& path) {
  const Json& picks = in.optionalMember(j, path, "picks");
  if (picks.is_null()) return std::nullopt;
  const std::string picksPath = FieldReader::join(path, "picks");
  PickCheck check;
  check.tried = in.count(picks, picksPath, "tried");
  check.mapped = in.count(picks, picksPath, "mapped");
  check.held = in.count(picks, picksPath, "held");
  const Json& aimed = in.optionalMember(picks, picksPath, "aimed_held");
  if (!aimed.is_null()) check.aimed_held = in.boolean(picks, picksPath, "aimed_held");
  return check;
}

MeshOutcome meshFromJson(const FieldReader& in, const Json& j, const std::string& path) {
  if (!j.is_object()) in.fail(path, "expected a JSON object");
  MeshOutcome mesh;
  mesh.contacts = in.intArray(j, path, "contacts");
  mesh.preselection_passed = in.boolean(j, path, "preselection_passed");
  mesh.task_fulfilled = in.boolean(j, path, "task_fulfilled");
  mesh.epsilon = in.number(j, path, "epsilon");
  mesh.reason = in.string(j, path, "reason");
  mesh.regions = regionsFromJson(in, j, path);
  // Absent (records written before snapping existed) or null: not computed.
  const Json& snapped = in.optionalMember(j, path, "snapped");
  if (!snapped.is_null()) mesh.snapped = snappedFromJson(in, snapped, FieldReader::join(path, "snapped"));
  mesh.picks = picksFromJson(in, j, path);
  const Json& conservative = in.optionalMember(j, path, "conservative");
  if (!conservative.is_null()) {
    const std::string conservativePath = FieldReader::join(path, "conservative");
    if (!conservative.is_array()) in.fail(conservativePath, "expected an array");
    for (std::size_t i = 0; i < conservative.size(); ++i) {
      const std::string itemPath = FieldReader::indexed(conservativePath, i);
      ConservativeOutcome c;
      c.sigmas = in.number(conservative[i], itemPath, "sigmas");
      c.regions = regionsFromJson(in, conservative[i], itemPath);
      c.picks = picksFromJson(in, conservative[i], itemPath);
      mesh.conservative.push_back(std::move(c));
    }
  }
  return mesh;
}

PatchMeshOutcome patchMeshFromJson(const FieldReader& in, const Json& j, const std::string& path) {
  if (!j.is_object()) in.fail(path, "expected a JSON object");
  PatchMeshOutcome mesh;
  mesh.task_fulfilled = in.boolean(j, path, "task_fulfilled");
  mesh.epsilon = in.number(j, path, "epsilon");
  mesh.reason = in.string(j, path, "reason");
  mesh.regions = regionsFromJson(in, j, path);
  if (!in.optionalMember(j, path, "aimed_held").is_null()) mesh.aimed_held = in.boolean(j, path, "aimed_held");
  return mesh;
}

PatchRecord patchFromJson(const FieldReader& in, const Json& j, const std::string& path) {
  if (!j.is_object()) in.fail(path, "expected a JSON object");
  PatchRecord patch;
  patch.radius_m = in.number(j, path, "radius_m");
  patch.filter_border = in.boolean(j, path, "filter_border");
  patch.evaluated = in.boolean(j, path, "evaluated");
  patch.cad_epsilon = in.number(j, path, "cad_epsilon");
  patch.tws_radius = in.number(j, path, "tws_radius");
  patch.cad_region_areas_m2 = in.doubleArray(j, path, "cad_region_areas_m2");
  patch.raw = patchMeshFromJson(in, in.member(j, path, "raw"), FieldReader::join(path, "raw"));
  patch.filtered = patchMeshFromJson(in, in.member(j, path, "filtered"), FieldReader::join(path, "filtered"));
  return patch;
}

bool isBlank(const std::string& line) {
  return std::all_of(line.begin(), line.end(), [](unsigned char c) { return c == ' ' || c == '\t' || c == '\r'; });
}

}  // namespace

bool GraspRecord::operator<(const GraspRecord& other) const {
  return std::tie(dataset, fingers, index) < std::tie(other.dataset, other.fingers, other.index);
}

std::string toJsonLine(const GraspRecord& record) {
  Json j;
  j["dataset"] = record.dataset;
  j["fingers"] = record.fingers;
  j["index"] = record.index;
  j["evaluated"] = record.evaluated;
  j["cad_contacts"] = record.cad_contacts;
  j["cad_epsilon"] = doubleToJson(record.cad_epsilon);
  j["tws_radius"] = doubleToJson(record.tws_radius);
  j["cad_region_areas_m2"] = doublesToJson(record.cad_region_areas_m2);
  j["raw"] = meshToJson(record.raw);
  j["filtered"] = meshToJson(record.filtered);
  if (record.seen_rim_distance_m) j["seen_rim_distance_m"] = doubleToJson(*record.seen_rim_distance_m);
  if (record.patch) j["patch"] = patchToJson(*record.patch);
  // Compact and ASCII-safe: one record per line whatever the dataset name holds
  // (dump escapes control characters, and invalid UTF-8 is replaced, not thrown).
  return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

GraspRecord fromJsonLine(const std::string& text, const std::string& source, std::size_t line) {
  const FieldReader in(source, line);
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::exception& e) {  // syntax, and numbers out of range (1e999)
    in.fail("", std::string("expected one JSON object (a grasp record): ") + e.what());
  }
  if (!j.is_object()) in.fail("", "expected one JSON object (a grasp record)");

  GraspRecord record;
  record.dataset = in.string(j, "", "dataset");
  record.fingers = in.count(j, "", "fingers");
  record.index = in.count(j, "", "index");
  record.evaluated = in.boolean(j, "", "evaluated");
  record.cad_contacts = in.intArray(j, "", "cad_contacts");
  record.cad_epsilon = in.number(j, "", "cad_epsilon");
  record.tws_radius = in.number(j, "", "tws_radius");
  record.cad_region_areas_m2 = in.doubleArray(j, "", "cad_region_areas_m2");
  record.raw = meshFromJson(in, in.member(j, "", "raw"), "raw");
  record.filtered = meshFromJson(in, in.member(j, "", "filtered"), "filtered");
  if (!in.optionalMember(j, "", "seen_rim_distance_m").is_null())
    record.seen_rim_distance_m = in.number(j, "", "seen_rim_distance_m");
  const Json& patch = in.optionalMember(j, "", "patch");
  if (!patch.is_null()) record.patch = patchFromJson(in, patch, "patch");
  return record;
}

std::vector<GraspRecord> readGraspRecords(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", std::string("cannot open the grasp records: ") + std::strerror(errno));
  std::vector<GraspRecord> records;
  std::string text;
  std::size_t line = 0;
  while (std::getline(in, text)) {
    ++line;
    if (isBlank(text)) continue;
    records.push_back(fromJsonLine(text, path, line));
  }
  if (in.bad()) throw InputError(path, "line " + std::to_string(line + 1), "read error");
  return records;
}

void writeGraspRecords(const std::string& path, const std::vector<GraspRecord>& records) {
  // Sorted, so that the file does not depend on the order in which a parallel
  // runner finished its grasps; stable, so that duplicates keep their order.
  std::vector<const GraspRecord*> order;
  order.reserve(records.size());
  for (const auto& record : records) order.push_back(&record);
  std::stable_sort(order.begin(), order.end(), [](const GraspRecord* a, const GraspRecord* b) { return *a < *b; });
  writeFileAtomically(path, [&](std::ostream& out) {
    for (const GraspRecord* record : order) out << toJsonLine(*record) << '\n';
  });
}

}  // namespace icrkit::eval
