#include <icrkit/core/attributes.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace icrkit {

std::size_t scalarSize(ScalarType type) {
  switch (type) {
    case ScalarType::Int8:
    case ScalarType::UInt8: return 1;
    case ScalarType::Int16:
    case ScalarType::UInt16: return 2;
    case ScalarType::Int32:
    case ScalarType::UInt32:
    case ScalarType::Float32: return 4;
    case ScalarType::Float64: return 8;
  }
  return 0;
}

const char* plyTypeName(ScalarType type) {
  switch (type) {
    case ScalarType::Int8: return "char";
    case ScalarType::UInt8: return "uchar";
    case ScalarType::Int16: return "short";
    case ScalarType::UInt16: return "ushort";
    case ScalarType::Int32: return "int";
    case ScalarType::UInt32: return "uint";
    case ScalarType::Float32: return "float";
    case ScalarType::Float64: return "double";
  }
  return "?";
}

bool isFloatingPoint(ScalarType type) { return type == ScalarType::Float32 || type == ScalarType::Float64; }

namespace {
template <typename T>
double clampRound(double value) {
  if (std::isnan(value)) return 0.0;
  double r = std::nearbyint(value);
  return std::clamp(r, static_cast<double>(std::numeric_limits<T>::lowest()),
                    static_cast<double>(std::numeric_limits<T>::max()));
}
}  // namespace

double representAs(ScalarType type, double value) {
  switch (type) {
    case ScalarType::Int8: return clampRound<std::int8_t>(value);
    case ScalarType::UInt8: return clampRound<std::uint8_t>(value);
    case ScalarType::Int16: return clampRound<std::int16_t>(value);
    case ScalarType::UInt16: return clampRound<std::uint16_t>(value);
    case ScalarType::Int32: return clampRound<std::int32_t>(value);
    case ScalarType::UInt32: return clampRound<std::uint32_t>(value);
    case ScalarType::Float32: return static_cast<double>(static_cast<float>(value));
    case ScalarType::Float64: return value;
  }
  return value;
}

const Attribute* AttributeSet::find(const std::string& name) const {
  for (const Attribute& a : attributes_)
    if (a.name == name) return &a;
  return nullptr;
}

Attribute* AttributeSet::find(const std::string& name) {
  for (Attribute& a : attributes_)
    if (a.name == name) return &a;
  return nullptr;
}

const Attribute& AttributeSet::get(const std::string& name) const {
  if (const Attribute* a = find(name)) return *a;
  throw std::out_of_range("no attribute named '" + name + "'");
}

Attribute& AttributeSet::get(const std::string& name) {
  if (Attribute* a = find(name)) return *a;
  throw std::out_of_range("no attribute named '" + name + "'");
}

Attribute& AttributeSet::add(const std::string& name, ScalarType type, std::size_t count, double fill) {
  return add(name, type, std::vector<double>(count, fill));
}

Attribute& AttributeSet::add(const std::string& name, ScalarType type, std::vector<double> values) {
  if (name.empty()) throw std::invalid_argument("an attribute needs a name");
  if (Attribute* existing = find(name)) {
    existing->type = type;
    existing->values = std::move(values);
    return *existing;
  }
  attributes_.push_back(Attribute{name, type, std::move(values)});
  return attributes_.back();
}

bool AttributeSet::remove(const std::string& name) {
  auto it = std::find_if(attributes_.begin(), attributes_.end(), [&](const Attribute& a) { return a.name == name; });
  if (it == attributes_.end()) return false;
  attributes_.erase(it);
  return true;
}

void AttributeSet::resize(std::size_t count) {
  for (Attribute& a : attributes_) a.values.resize(count, 0.0);
}

void AttributeSet::select(const std::vector<std::size_t>& indices) {
  for (Attribute& a : attributes_) {
    std::vector<double> kept;
    kept.reserve(indices.size());
    for (std::size_t i : indices) kept.push_back(a.values.at(i));
    a.values = std::move(kept);
  }
}

}  // namespace icrkit
