#pragma once
/// \file
/// The paper's household objects (Krug et al., Fig. 2) as CAD meshes, built
/// procedurally: cup with handle, paper cup, bottle, coffee pot and two
/// wooden toys. Real sizes in metres; watertight, edge-manifold, wound
/// counter-clockwise seen from outside, with unit vertex normals.
///
/// Object frame: the object stands on the plane z = 0 (its lowest point at
/// z = 0), centred on the z axis (the centre of its bounding box has x = y =
/// 0), z up.

#include <icrkit/core/triangle_mesh.hpp>

#include <string>
#include <vector>

namespace icrkit::sim {

enum class CadObject { Cup, PaperCup, Bottle, CoffeePot, WoodenToy1, WoodenToy2 };

/// "cup", "paper_cup", "bottle", "coffee_pot", "wooden_toy_1", "wooden_toy_2",
/// in the enum's order.
const std::vector<std::string>& cadObjectNames();
std::string cadObjectName(CadObject object);
/// Throws InputError("--object", "", "unknown object 'x', expected one of ...").
CadObject parseCadObject(const std::string& name);

/// The object's mesh: 20k-60k vertices, deterministic (no randomness).
TriangleMesh makeCadObject(CadObject object);

}  // namespace icrkit::sim
