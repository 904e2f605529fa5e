#pragma once
/// \file
/// Named per-element attributes (per point, per vertex), e.g. `cardinality`,
/// `flatness`, `excluded`, `region` (docs/formats.md lists the shared names
/// and which command writes each).
///
/// Values are held as double, which represents every PLY/PCD scalar type
/// exactly; the declared scalar type is what a writer puts in the file, so
/// that `excluded` stays a uchar and `region` an int through a round trip.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

namespace icrkit {

enum class ScalarType : std::uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

/// Size in bytes of one value of the type.
std::size_t scalarSize(ScalarType type);
/// PLY spelling: "char", "uchar", "short", "ushort", "int", "uint", "float", "double".
const char* plyTypeName(ScalarType type);
/// True for Float32 and Float64.
bool isFloatingPoint(ScalarType type);
/// Rounds/clamps `value` to what the type can hold (NaN stays NaN for floats, 0 for integers).
double representAs(ScalarType type, double value);

struct Attribute {
  std::string name;
  ScalarType type = ScalarType::Float32;
  std::vector<double> values;
};

/// An ordered set of attributes, all of the same length as their owner's elements.
/// Insertion order is kept so that files round-trip with their columns in place.
/// References returned by add()/get() stay valid when further attributes are
/// added (a deque, not a vector, holds them); remove() invalidates them.
class AttributeSet {
public:
  bool has(const std::string& name) const { return find(name) != nullptr; }
  const Attribute* find(const std::string& name) const;
  Attribute* find(const std::string& name);
  /// Throws std::out_of_range naming the attribute when absent.
  const Attribute& get(const std::string& name) const;
  Attribute& get(const std::string& name);

  /// Adds (or replaces) an attribute with `count` copies of `fill`.
  Attribute& add(const std::string& name, ScalarType type, std::size_t count, double fill = 0.0);
  /// Adds (or replaces) an attribute with the given values.
  Attribute& add(const std::string& name, ScalarType type, std::vector<double> values);
  bool remove(const std::string& name);

  /// Resizes every attribute, new entries set to 0.
  void resize(std::size_t count);
  /// Keeps only the elements whose index is listed, in that order.
  void select(const std::vector<std::size_t>& indices);

  std::size_t size() const { return attributes_.size(); }
  bool empty() const { return attributes_.empty(); }
  std::deque<Attribute>::const_iterator begin() const { return attributes_.begin(); }
  std::deque<Attribute>::const_iterator end() const { return attributes_.end(); }
  std::deque<Attribute>::iterator begin() { return attributes_.begin(); }
  std::deque<Attribute>::iterator end() { return attributes_.end(); }

private:
  std::deque<Attribute> attributes_;
};

}  // namespace icrkit
