#pragma once
// The flags and inputs of `icrkit render`: the meshes and regions files it reads, the view size, the
// cameras (automatic orbit or --camera eyes, fitted to the mesh) and the
// prototype contacts to mark.

#include "command_context.hpp"

#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/report/mesh_render.hpp>

#include <CLI/CLI.hpp>

#include <string>
#include <utility>
#include <vector>

namespace icrkit::app {

struct RenderOptions {
  std::string mesh;
  std::string regions;
  std::string compare;
  std::string compare_regions;
  std::string contacts;
  bool compute_normals = false;
  int finger = -1;  ///< -1: every finger
  std::string size = "800x600";
  int views = 4;
  bool top_view = false;
  std::vector<std::string> cameras;
  std::string up = "0,0,1";
  int columns = 0;  ///< 0: automatic
  int samples = 2;
  bool central_points = true;
  std::string output;
};

// The regions of one mesh, as the regions file holds them, finger by finger.
struct RegionSet {
  std::vector<int> fingers;
  std::vector<int> contacts;  ///< -1 when the entry has none
  std::vector<std::vector<int>> vertices;

  std::vector<int> setContacts() const;  ///< the contacts that are not -1
};

/// Reads a regions file (icr/regions_file.hpp) of `mesh` (read from
/// `mesh_path`); only finger `finger` when it is >= 0 (an absent finger is
/// an error naming --finger).
RegionSet readRegions(const std::string& path, const TriangleMesh& mesh, const std::string& mesh_path, int finger);

/// The mesh to render; with `compute_normals` normals from the faces (a
/// note when windings conflict), else with `need_normals` the file's
/// normals are required.
TriangleMesh readMesh(const std::string& path, bool need_normals, bool compute_normals, CommandContext& context);

/// Adds every flag of the command (MESH and -o included) to `command`.
void addRenderOptions(CLI::App& command, RenderOptions& options);

/// --size WIDTHxHEIGHT in pixels.
std::pair<int, int> parseSize(const std::string& text);

/// --contacts i,j,...: vertices of `mesh` that some face uses.
std::vector<int> parseContacts(const std::string& text, const TriangleMesh& mesh);

/// The views: one per --camera (fitted to the mesh's bounding sphere) or
/// the automatic orbit (--views, --top-view), all with --up.
std::vector<report::RenderCamera> chooseCameras(const RenderOptions& options, const TriangleMesh& mesh, int width,
                                                int height);

}  // namespace icrkit::app
