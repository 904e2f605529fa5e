#pragma once
/// \file
/// Headless images of a mesh (no display, no GPU): every pixel is ray-cast
/// with the core Embree RayCaster, shaded with two-sided Lambert lighting and
/// coloured per vertex or per face; markers (contacts, central points) are
/// drawn on top as discs; several views are tiled into one image with
/// captions and a legend, and written as PNG.
///
/// Conventions
///   - Images are RGB, 8 bits per channel, rows top to bottom.
///   - Colours given as Eigen::Vector3f are linear 0..1 per channel; the
///     output byte is round(255 * clamp(value)). No gamma handling: these are
///     diagrams, not photographs.
///   - Every output is a deterministic function of the inputs (rows are
///     rendered in parallel, but each pixel only depends on its own rays).
///
/// The end of this file holds the ICR colouring: a finger palette, regions
/// per finger and the Fig. 6 style comparison of a CAD region with a
/// reconstructed one.

#include <icrkit/core/ray_caster.hpp>
#include <icrkit/core/triangle_mesh.hpp>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace icrkit::report {

struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< width * height * 3 bytes, row-major, top row first

  RgbImage() = default;
  /// A width x height image filled with `fill`.
  RgbImage(int width, int height, const std::array<std::uint8_t, 3>& fill = {255, 255, 255});

  std::array<std::uint8_t, 3> at(int x, int y) const;
  void set(int x, int y, const std::array<std::uint8_t, 3>& colour);
};

/// A pinhole camera. The image's vertical extent spans `vertical_fov_rad`;
/// the horizontal one follows from the image's aspect ratio (square pixels).
struct RenderCamera {
  Eigen::Vector3d eye = Eigen::Vector3d(0.0, 0.0, 1.0);  ///< metres
  Eigen::Vector3d target = Eigen::Vector3d::Zero();      ///< looked at; projects to the image centre
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();         ///< need not be orthogonal to the view direction
  double vertical_fov_rad = 0.6;                         ///< in (0, pi)
  std::string name;                                      ///< caption, e.g. "front"; may be empty
};

/// The smallest sphere around the axis-aligned bounds' centre that holds
/// every vertex some face uses (every vertex of a mesh without faces; not the
/// minimal enclosing sphere, but within a factor sqrt(3) of it and cheap).
struct BoundingSphere {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 0.0;  ///< metres
};
/// Throws InputError("mesh", ...) for a mesh without vertices.
BoundingSphere boundingSphere(const TriangleMesh& mesh);

struct OrbitParameters {
  /// Number of views, >= 1. Views are spread evenly around `up` (azimuth
  /// step 360 / ring size), starting from the front: the camera on the -y
  /// side of the object (for up = +z) looking towards +y.
  int count = 4;
  /// Replaces the last view of the ring by one looking straight down along
  /// -up (only when count >= 2).
  bool top_view = false;
  double elevation_rad = 0.45;  ///< ring views look down from this angle above the horizon (~26 deg)
  double vertical_fov_rad = 0.6;  ///< ~34 deg
  double aspect = 4.0 / 3.0;      ///< image width / height, to fit the horizontal extent too
  /// The bounding sphere, times this factor, just fits into the narrower
  /// image extent: > 1 leaves a margin.
  double margin = 1.05;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  ///< the object's up axis (icrkit datasets: z up)
};

/// Cameras around the mesh's bounding sphere, each fitted so that the whole
/// mesh is in view. Names: "front", "right", "back", "left" at azimuths 0,
/// 90, 180, 270 degrees, "azimuth A" (degrees) between them, "top". Throws InputError
/// for a mesh without vertices or parameters out of range.
std::vector<RenderCamera> orbitCameras(const TriangleMesh& mesh, const OrbitParameters& params = {});

/// A camera at `eye` looking at `target` with the field of view that just
/// fits `sphere` (times `margin`) into an image of the given aspect; an eye
/// inside the sphere gets a 90 degree field of view. InputError when eye ==
/// target or up is parallel to the view direction.
RenderCamera fittedCamera(const BoundingSphere& sphere, const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                          const Eigen::Vector3d& up, double aspect, double margin = 1.05);

struct RenderStyle {
  int width = 800;   ///< pixels, >= 1
  int height = 600;  ///< pixels, >= 1
  /// Rays per pixel along each axis (k x k jittered-free grid, box-filtered):
  /// 1 = aliased edges, 2 = smooth enough for figures. 1..8.
  int samples_per_axis = 2;
  Eigen::Vector3f background = Eigen::Vector3f(1.0f, 1.0f, 1.0f);
  /// Albedo of surface not coloured otherwise (no colours given).
  Eigen::Vector3f base_colour = Eigen::Vector3f(0.78f, 0.78f, 0.78f);
  /// Lighting: colour = albedo * (ambient + headlight * |n.v| + key * max(0, n.l)),
  /// where n is turned towards the viewer (two-sided), v points to the eye and
  /// l is `key_direction_camera` in camera coordinates (x right, y up, z
  /// towards the viewer), so every view is lit alike. The weights sum to 1.0
  /// so that a surface facing both lights shows its albedo.
  float ambient = 0.25f;
  float headlight = 0.45f;
  float key = 0.30f;
  Eigen::Vector3d key_direction_camera = Eigen::Vector3d(-0.5, 0.7, 0.5);
  /// Interpolate the mesh's vertex normals (when it has them) for shading;
  /// false, or no normals: flat shading with the face normal.
  bool smooth_shading = true;
  /// A marker is hidden when the surface along the ray from the eye to its
  /// centre is hit more than this fraction of the mesh's bounding radius
  /// before it (markers on the surface itself stay visible).
  double marker_depth_tolerance = 0.01;
};

/// How vertex colours spread over a face.
enum class VertexColouring {
  /// Each point of a face takes the colour of its nearest corner (largest
  /// barycentric weight): a vertex set shows as crisp patches, and a region
  /// border runs halfway between member and non-member vertices.
  NearestVertex,
  /// Barycentric blend of the three corner colours (soft borders).
  Interpolated
};

/// Surface albedo, from the first of these that is not empty:
///   - `per_face`: one colour per face (flat);
///   - `per_corner`: three per face (face f's corner k at 3 f + k), spread
///     over the face by `vertex_colouring`; lets a vertex look different in
///     each of its faces;
///   - `per_vertex`: one per vertex, spread by `vertex_colouring`;
/// else the style's base colour everywhere.
struct SurfaceColours {
  std::vector<Eigen::Vector3f> per_vertex;
  std::vector<Eigen::Vector3f> per_corner;
  std::vector<Eigen::Vector3f> per_face;
  VertexColouring vertex_colouring = VertexColouring::NearestVertex;
};

/// A dot drawn on top of the shaded surface when its centre is visible (see
/// RenderStyle::marker_depth_tolerance): the whole disc then shows, even
/// where it overhangs a silhouette, so that a contact on the rim stays
/// legible. Markers are drawn in the order given (later ones on top).
struct Marker {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< metres
  Eigen::Vector3f colour = Eigen::Vector3f::Zero();
  double radius_px = 5.0;                               ///< output pixels, > 0
  /// Ring around the disc (0 = none), in output pixels, drawn in `outline_colour`.
  double outline_px = 1.5;
  Eigen::Vector3f outline_colour = Eigen::Vector3f(1.0f, 1.0f, 1.0f);
};

/// Renders one mesh from many cameras; the acceleration structure is built
/// once. Keeps a reference to the mesh, which must outlive the renderer.
/// render() is const and may be called concurrently.
class MeshRenderer {
public:
  /// Throws InputError("mesh", ...) for a mesh without faces or an invalid one.
  explicit MeshRenderer(const TriangleMesh& mesh);

  /// Throws InputError for a style out of range (source "render style"), a
  /// degenerate camera (source "camera") or colours of the wrong count
  /// (source "colours").
  RgbImage render(const RenderCamera& camera, const RenderStyle& style, const SurfaceColours& colours = {},
                  const std::vector<Marker>& markers = {}) const;

  const BoundingSphere& sphere() const { return sphere_; }

private:
  const TriangleMesh* mesh_;
  RayCaster caster_;
  BoundingSphere sphere_;
};

/// One-off convenience: MeshRenderer(mesh).render(...).
RgbImage renderMesh(const TriangleMesh& mesh, const RenderCamera& camera, const RenderStyle& style,
                    const SurfaceColours& colours = {}, const std::vector<Marker>& markers = {});

/// `caption` in the top-left corner of `image` (dark text on a light box).
void drawCaption(RgbImage& image, const std::string& caption);

/// Images laid out left to right, top to bottom, `columns` per row; each cell
/// as large as the largest image, smaller images at its top-left, the rest
/// filled with `fill`. Throws InputError("tiles", ...) for no images or
/// columns < 1.
RgbImage tileImages(const std::vector<RgbImage>& images, int columns,
                    const std::array<std::uint8_t, 3>& fill = {255, 255, 255});

struct LegendEntry {
  Eigen::Vector3f colour = Eigen::Vector3f::Zero();
  std::string label;
  bool dot = false;  ///< a disc (marker) swatch instead of a square (surface) swatch
};

/// `image` with a white strip below it holding the entries left to right
/// (wrapping onto more lines when needed): a swatch and the label each.
/// The strip is legendHeight(image.width, entries) pixels tall; no entries,
/// no strip.
RgbImage appendLegend(const RgbImage& image, const std::vector<LegendEntry>& entries);
int legendHeight(int width, const std::vector<LegendEntry>& entries);

/// PNG bytes of `image` (lossless).
std::string encodePng(const RgbImage& image);
/// Writes `image` as PNG atomically (InputError naming `path` on failure).
void writePng(const std::string& path, const RgbImage& image);

// --- ICR colouring -----------------------------------------------------

/// Colour of finger `finger` (>= 0): the Okabe-Ito palette (colour-blind
/// safe) without black, ordered so that the usual 3-5 fingers get the most
/// distinct hues: orange, sky blue, bluish green, reddish purple, blue,
/// yellow, vermillion; more fingers reuse them.
Eigen::Vector3f fingerColour(int finger);

/// Colours of the comparison (Fig. 6 of the paper, in our own colours).
struct ComparisonPalette {
  /// CAD faces in I_n (reached by a normal line of the reconstructed
  /// region), and reconstructed region vertices whose line reached C_n^C.
  Eigen::Vector3f intersection = Eigen::Vector3f(0.0f, 158.0f / 255.0f, 115.0f / 255.0f);  ///< bluish green
  /// CAD region faces not in I_n: ground truth the reconstruction missed.
  Eigen::Vector3f missed = Eigen::Vector3f(0.0f, 114.0f / 255.0f, 178.0f / 255.0f);  ///< blue
  /// Reconstructed region vertices whose line missed C_n^C (FP area).
  Eigen::Vector3f false_positive = Eigen::Vector3f(213.0f / 255.0f, 94.0f / 255.0f, 0.0f);  ///< vermillion
};

/// Per-vertex albedo: each region's vertices in fingerColour(finger), the
/// rest `base`. A vertex in several regions takes the lowest finger (as the
/// `region` property of `icrkit icr`). `regions[i]` is the region of finger
/// `fingers[i]`. InputError("region", "finger f, element k", ...) for a
/// vertex index out of range.
std::vector<Eigen::Vector3f> regionColours(const TriangleMesh& mesh, const std::vector<int>& fingers,
                                           const std::vector<std::vector<int>>& regions,
                                           const Eigen::Vector3f& base);

/// Per-face albedo of the CAD mesh: faces of some C_n^C (all three corners
/// in the region, the faces A(C_n^C) counts) in `palette.missed`, faces of
/// some I_n in `palette.intersection` (intersection wins where regions of
/// several fingers meet), the rest `base`. Faces, not vertices, because
/// I_n and its area are defined on faces. InputError for indices out of range.
std::vector<Eigen::Vector3f> cadComparisonColours(const TriangleMesh& cad,
                                                  const std::vector<std::vector<int>>& cad_regions,
                                                  const std::vector<std::vector<int>>& intersection_faces,
                                                  const Eigen::Vector3f& base, const ComparisonPalette& palette = {});

/// Per-corner albedo (SurfaceColours::per_corner) of the reconstructed mesh,
/// drawn as the FP area is measured: each triangle of some C_n^S (all three
/// corners in the region) gives each corner a third of its area, so each
/// such corner is coloured by its verdict, `palette.intersection` when its
/// line reached C_n^C (`inside[n][k]` for `scan_regions[n][k]`, as
/// RegionIntersection::inside) and `palette.false_positive` when not
/// (inside wins where regions of several fingers meet); every other corner
/// is `base`. Rendered with VertexColouring::NearestVertex, where each
/// corner owns exactly a third of the triangle, the vermillion area on the
/// surface is the FP area, and a region vertex in no region triangle (which
/// carries no area) shows nothing. InputError for indices out of range.
std::vector<Eigen::Vector3f> scanComparisonColours(const TriangleMesh& scan,
                                                   const std::vector<std::vector<int>>& scan_regions,
                                                   const std::vector<std::vector<std::uint8_t>>& inside,
                                                   const Eigen::Vector3f& base, const ComparisonPalette& palette = {});

}  // namespace icrkit::report
