#include "cad_object_shapes.hpp"

#include "sdf_primitives.hpp"

#include <cmath>
#include <stdexcept>

namespace icrkit::sim {
namespace {

using namespace sdf;

constexpr double mm = 1e-3;
constexpr double kPi = 3.14159265358979323846;

// Flat faces lie this fraction of a cell beyond the last grid plane inside
// the solid: marching cubes then cuts their convex edges by only about a
// tenth of a cell. The toys get it from their dimensions, which end in .1
// or .9 mm on a grid with nodes at whole millimetres; the other objects
// from the grid's anchor, for their flat bottoms (docs/cad_objects.md).
constexpr double kFaceOffset = 0.1;

Vector2d v2(double a, double b) { return Vector2d(a, b) * mm; }
Vector3d v3(double a, double b, double c) { return Vector3d(a, b, c) * mm; }

// Solid z >= 0 with its bottom edge rounded over about k (smooth maximum).
double smoothIntersect(double a, double b, double k) { return -smoothUnite(-a, -b, k); }

// Solid of revolution bounded by rho = r(z): the radial gap divided by the
// profile's slope factor, a first-order distance whose zero set is exact.
double revolvedProfile(const Vector3d& p, double radius, double slope) {
  return (std::hypot(p.x(), p.y()) - radius) / std::sqrt(1.0 + slope * slope);
}

// ---- Cup with handle: a ceramic mug --------------------------------------

double cup(const Vector3d& p) {
  const Vector2d q = meridian(p);
  // Wall 4 mm thick, rim and foot rounded to 1.9 mm; the floor is raised
  // 2.5 mm inside the foot ring and filleted into the wall.
  const double wall = roundBox2(q - v2(38, 45), v2(2, 45), 1.9 * mm);
  const double floor = box2(q - v2(0, 5.25), v2(37, 2.75));
  const double body = smoothUnite(wall, floor, 2 * mm);
  // Handle: a ring of elliptic section in the x-z plane, cut off inside the
  // wall (beyond reach of the fillet from the cup's inside).
  const double ring = ellipticRingXZ(p, v3(44, 0, 48), 22 * mm, 4.5 * mm, 6 * mm);
  const double handle = intersect(ring, 38.5 * mm - p.x());
  return smoothUnite(body, handle, 3 * mm);
}

// ---- Paper cup: thin conical wall, rolled rim, inset bottom disc ----------

double paperCup(const Vector3d& p) {
  const Vector2d q = meridian(p);
  // Wall 2.4 mm thick (paper is 0.3-0.5 mm; the grid needs two cells).
  const double wall = capsule2(q, v2(27, 1.2), v2(40, 89), 1.2 * mm);
  const double rim = circle2(q, v2(41, 89.3), 2.0 * mm);
  const double bottom = box2(q - v2(0, 10), v2(28.5, 1.2));
  return smoothUnite(smoothUnite(wall, rim, 0.8 * mm), bottom, 0.8 * mm);
}

// ---- Bottle: 0.5 l PET bottle with shoulder, neck, support ring and cap ---

double bottle(const Vector3d& p) {
  const Vector2d q = meridian(p);
  // Body radius 32.5 mm up to z = 138 mm, a cosine shoulder down to the
  // neck's 13.5 mm at z = 180 mm.
  const double z = p.z() / mm;
  double radius = 32.5, slope = 0.0;
  if (z > 180.0) {
    radius = 13.5;
  } else if (z > 138.0) {
    const double u = kPi * (z - 138.0) / 42.0;
    radius = 13.5 + 9.5 * (1.0 + std::cos(u));
    slope = -9.5 * std::sin(u) * kPi / 42.0;
  }
  double d = revolvedProfile(p, radius * mm, slope);
  d = smoothIntersect(d, -p.z(), 8 * mm);  // rounded bottom edge
  d = intersect(d, p.z() - 192 * mm);      // neck top, under the cap
  for (double groove : {52.0, 100.0}) d = smoothSubtract(d, circle2(q, v2(35, groove), 3.5 * mm), 1.5 * mm);
  const double support_ring = roundBox2(q - v2(0, 181.5), v2(17, 1.2), 0.6 * mm);
  const double cap = roundBox2(q - v2(0, 196), v2(15, 9), 1.5 * mm);
  d = unite(unite(d, support_ring), cap);
  // Push-up in the base: the bottle stands on a ring.
  return smoothSubtract(d, circle2(q, v2(0, -30), 37 * mm), 2 * mm);
}

// ---- Coffee pot: bellied body, spout, handle, lid with knob ---------------

double coffeePot(const Vector3d& p) {
  const Vector2d q = meridian(p);
  // Body radius 50 mm at the foot, 56 mm at z = 50 mm, 45 mm at the top
  // (z = 135 mm): two parabolas meeting with zero slope.
  const double z = p.z() / mm;
  const double zc = std::clamp(z, 0.0, 135.0);
  const double c = zc <= 50.0 ? 6.0 / 2500.0 : 11.0 / 7225.0;
  const double radius = 56.0 - c * (zc - 50.0) * (zc - 50.0);
  const double slope = -2.0 * c * (zc - 50.0);
  double body = revolvedProfile(p, radius * mm, slope);
  body = smoothIntersect(body, -p.z(), 8 * mm);
  body = smoothIntersect(body, p.z() - 135 * mm, 4 * mm);

  // Spout: a cone frustum leaning outwards, its lip rounded by 1 mm, with a
  // 45 mm deep bore from the tip.
  const Vector3d a = v3(38, 0, 40), b = v3(92, 0, 138);
  const Vector3d axis = (b - a).normalized();
  const double spout = cappedCone(p, a, b - axis * mm, 12 * mm, 6.5 * mm) - 1 * mm;
  const double bore = cappedCone(p, b + 5 * mm * axis, b - 45 * mm * axis, 4 * mm, 3.2 * mm);

  const double ring = ellipticRingXZ(p, v3(-60, 0, 80), 34 * mm, 6 * mm, 8 * mm);
  const double handle = intersect(ring, p.x() + 46 * mm);

  double pot = smoothUnite(smoothUnite(body, spout, 6 * mm), handle, 5 * mm);
  pot = smoothSubtract(pot, bore, 1 * mm);

  const double flange = roundBox2(q - v2(0, 137), v2(48.5, 3), 2 * mm);
  const double dome = intersect(circle2(q, v2(0, 108), 48 * mm), 138 * mm - p.z());
  const double knob = smoothUnite(roundBox2(q - v2(0, 161), v2(5, 8), 1.5 * mm), sphere(p, v3(0, 0, 171), 9 * mm),
                                  3 * mm);
  const double lid = smoothUnite(smoothUnite(flange, dome, 3 * mm), knob, 4 * mm);
  return unite(pot, lid);
}

// ---- Wooden toy 1: bridge block with a bore, a square slot and a peg -----

double woodenToy1(const Vector3d& p) {
  double d = box(p, v3(-60.1, -25.1, -0.1), v3(60.1, 25.1, 40.1));
  d = subtract(d, cylinder(p, 1, v3(0, 0, -0.1), 19.9 * mm, -30 * mm, 30 * mm));  // arch
  d = subtract(d, cylinder(p, 2, v3(38, 0, 0), 9.9 * mm, -5 * mm, 45 * mm));      // vertical bore
  d = subtract(d, box(p, v3(-7.9, -30, 25.1), v3(7.9, 30, 32.9)));                // square slot
  return unite(d, cylinder(p, 2, v3(-38, 0, 0), 10.1 * mm, 30 * mm, 75.1 * mm));  // peg
}

// ---- Wooden toy 2: car of blocks with a window and four wheels ----------

double woodenToy2(const Vector3d& p) {
  const double chassis = box(p, v3(-50.1, -20.1, 7.9), v3(50.1, 20.1, 28.1));
  const double cabin = box(p, v3(-40.1, -20.1, 20), v3(10.1, 20.1, 50.1));
  const double window = box(p, v3(-31.9, -30, 32.1), v3(-8.1, 30, 45.9));
  double d = unite(chassis, subtract(cabin, window));
  for (double x : {-32.0, 32.0}) {
    const Vector3d hub_centre = v3(x, 0, 14);
    d = unite(d, cylinder(p, 1, hub_centre, 4 * mm, -26 * mm, 26 * mm));  // axle
    for (double side : {-1.0, 1.0}) {
      const double wheel = cylinder(p, 1, hub_centre, 14 * mm, side * 23.9 * mm, side * 32.1 * mm);
      const double hub = cylinder(p, 1, hub_centre, 5 * mm, side * 30 * mm, side * 35.1 * mm);
      d = unite(d, unite(wheel, hub));
    }
  }
  return d;
}

Eigen::AlignedBox3d box3(const Vector3d& lo, const Vector3d& hi) { return Eigen::AlignedBox3d(lo, hi); }

}  // namespace

CadShape cadShape(CadObject object) {
  CadShape shape;
  switch (object) {
    case CadObject::Cup:
      shape = {cup, box3(v3(-40, -40, 0), v3(70.5, 40, 90)), 1.3 * mm, {}};
      break;
    case CadObject::PaperCup:
      shape = {paperCup, box3(v3(-43, -43, 0), v3(43, 43, 91.3)), 1.15 * mm, {}};
      break;
    case CadObject::Bottle:
      shape = {bottle, box3(v3(-32.5, -32.5, 0), v3(32.5, 32.5, 205)), 1.1 * mm, {}};
      break;
    case CadObject::CoffeePot:
      shape = {coffeePot, box3(v3(-100, -56, 0), v3(99, 56, 180)), 1.5 * mm, {}};
      break;
    case CadObject::WoodenToy1:
      shape = {woodenToy1, box3(v3(-60.1, -25.1, -0.1), v3(60.1, 25.1, 75.1)), 1.0 * mm, {}};
      break;
    case CadObject::WoodenToy2:
      shape = {woodenToy2, box3(v3(-50.1, -35.1, 0), v3(50.1, 35.1, 50.1)), 1.0 * mm, {}};
      break;
    default:
      throw std::invalid_argument("cadShape: unknown object");
  }
  const bool toy = object == CadObject::WoodenToy1 || object == CadObject::WoodenToy2;
  // The toys' dimensions are chosen for nodes at whole millimetres; the
  // other objects have a node kFaceOffset cells above their flat bottom.
  shape.anchor = toy ? Vector3d::Zero() : Vector3d(0, 0, kFaceOffset * shape.cell);
  return shape;
}

SampleGrid cadShapeGrid(const CadShape& shape) { return gridAround(shape.bounds, shape.cell, shape.anchor); }

}  // namespace icrkit::sim
