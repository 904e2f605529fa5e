// Headless renders of a known scene: a unit sphere seen from +z with its cap
// z > 0.8 as one region; pixel colours at places whose content is known.

#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_primitives.hpp>
#include <icrkit/report/mesh_render.hpp>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace icrkit::report {
namespace {


using Pixel = std::array<std::uint8_t, 3>;

const Eigen::Vector3f kRed(1.0f, 0.0f, 0.0f);

// The camera 4 units up the z axis looking at the origin; 0.6 rad vertical
// field of view: the sphere (angular radius asin(1/4) = 0.25 rad) fills
// about 80 % of the image height.
RenderCamera frontCamera() {
  RenderCamera camera;
  camera.eye = Eigen::Vector3d(0.0, 0.0, 4.0);
  camera.target = Eigen::Vector3d::Zero();
  camera.up = Eigen::Vector3d::UnitY();
  camera.vertical_fov_rad = 0.6;
  return camera;
}

RenderStyle smallStyle() {
  RenderStyle style;
  style.width = 160;
  style.height = 120;
  return style;
}

struct Scene {
  TriangleMesh sphere = makeIcosphere(4, 1.0);
  std::vector<int> region;
  Scene() {
    for (std::size_t v = 0; v < sphere.vertexCount(); ++v)
      if (sphere.vertices.positions[v].z() > 0.8) region.push_back(static_cast<int>(v));
  }
  SurfaceColours colours(const RenderStyle& style) const {
    SurfaceColours c;
    c.per_vertex = regionColours(sphere, {0}, {region}, style.base_colour);
    for (int v : region) c.per_vertex[static_cast<std::size_t>(v)] = kRed;
    return c;
  }
};

// Pixel (x, y) of an image of size w x h that sees direction ndc (-1..1).
int column(double ndc_x, int width) { return static_cast<int>((ndc_x + 1.0) * 0.5 * width); }
int row(double ndc_y, int height) { return static_cast<int>((1.0 - ndc_y) * 0.5 * height); }

// Where the sphere point p projects in the front camera's image.
std::pair<int, int> project(const Eigen::Vector3d& p, const RenderStyle& style) {
  const double tan_half = std::tan(0.3), depth = 4.0 - p.z();
  const double aspect = static_cast<double>(style.width) / style.height;
  return {column(p.x() / depth / (tan_half * aspect), style.width), row(p.y() / depth / tan_half, style.height)};
}

TEST(MeshRender, KnownSphereSceneHasKnownPixels) {
  const Scene scene;
  const RenderStyle style = smallStyle();
  const RgbImage image = renderMesh(scene.sphere, frontCamera(), style, scene.colours(style));
  ASSERT_EQ(image.width, 160);
  ASSERT_EQ(image.height, 120);
  ASSERT_EQ(image.rgb.size(), 160u * 120u * 3u);

  // Centre: the region, facing the camera and the headlight: red, shaded.
  const Pixel centre = image.at(80, 60);
  EXPECT_GT(centre[0], 150);
  EXPECT_EQ(centre[1], 0);
  EXPECT_EQ(centre[2], 0);

  // Corners and a point just right of the sphere's silhouette: background, exactly.
  for (const auto& [x, y] : {std::pair{0, 0}, std::pair{159, 119}, std::pair{5, 60}, std::pair{150, 10}})
    EXPECT_EQ(image.at(x, y), (Pixel{255, 255, 255})) << x << "," << y;

  // On the sphere outside the cap (a point at 45 degrees from the axis):
  // the grey base colour, shaded: equal channels, darker than the albedo.
  const auto [gx, gy] = project(Eigen::Vector3d(std::sqrt(0.5), 0.0, std::sqrt(0.5)), style);
  const Pixel grey = image.at(gx, gy);
  EXPECT_EQ(grey[0], grey[1]);
  EXPECT_EQ(grey[1], grey[2]);
  EXPECT_GT(grey[0], 60);
  EXPECT_LT(grey[0], 200);
}

TEST(MeshRender, SizeIsHonouredAndOutputDeterministic) {
  const Scene scene;
  RenderStyle style = smallStyle();
  style.width = 37;
  style.height = 91;
  const RgbImage a = renderMesh(scene.sphere, frontCamera(), style, scene.colours(style));
  const RgbImage b = renderMesh(scene.sphere, frontCamera(), style, scene.colours(style));
  EXPECT_EQ(a.width, 37);
  EXPECT_EQ(a.height, 91);
  EXPECT_EQ(a.rgb, b.rgb);
}

TEST(MeshRender, VisibleMarkerIsDrawnAndHiddenOneIsNot) {
  const Scene scene;
  const RenderStyle style = smallStyle();
  const RgbImage plain = renderMesh(scene.sphere, frontCamera(), style, scene.colours(style));

  Marker front;
  front.position = Eigen::Vector3d(0.0, 0.0, 1.0);  // the sphere's point nearest the camera
  front.colour = Eigen::Vector3f(0.0f, 0.0f, 1.0f);
  front.radius_px = 5.0;
  const RgbImage shown = renderMesh(scene.sphere, frontCamera(), style, scene.colours(style), {front});
  EXPECT_EQ(shown.at(80, 60), (Pixel{0, 0, 255}));
  // Outside the disc and its outline nothing changed.
  EXPECT_EQ(shown.at(80, 40), plain.at(80, 40));

  Marker back = front;
  back.position = Eigen::Vector3d(0.0, 0.0, -1.0);  // behind the sphere
  const RgbImage hidden = renderMesh(scene.sphere, frontCamera(), style, scene.colours(style), {back});
  EXPECT_EQ(hidden.rgb, plain.rgb);
}

TEST(MeshRender, FaceColoursWinOverVertexColours) {
  const Scene scene;
  const RenderStyle style = smallStyle();
  SurfaceColours colours = scene.colours(style);
  colours.per_face.assign(scene.sphere.faceCount(), Eigen::Vector3f(0.0f, 1.0f, 0.0f));
  const Pixel centre = renderMesh(scene.sphere, frontCamera(), style, colours).at(80, 60);
  EXPECT_EQ(centre[0], 0);
  EXPECT_GT(centre[1], 150);
  EXPECT_EQ(centre[2], 0);
}

TEST(MeshRender, PngRoundTripsToTheSamePixels) {
  const Scene scene;
  const RenderStyle style = smallStyle();
  RgbImage image = renderMesh(scene.sphere, frontCamera(), style, scene.colours(style));
  drawCaption(image, "front");
  const auto path = std::filesystem::temp_directory_path() / "icrkit_mesh_render_test.png";
  writePng(path.string(), image);
  std::ifstream in(path, std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::filesystem::remove(path);
  ASSERT_GT(bytes.size(), 8u);
  const cv::Mat bgr = cv::imdecode(bytes, cv::IMREAD_COLOR);
  ASSERT_EQ(bgr.cols, image.width);
  ASSERT_EQ(bgr.rows, image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
      ASSERT_EQ((Pixel{p[2], p[1], p[0]}), image.at(x, y)) << x << "," << y;
    }
}

TEST(MeshRender, BadInputIsAnInputError) {
  const Scene scene;
  RenderStyle style = smallStyle();
  style.width = 0;
  EXPECT_THROW(renderMesh(scene.sphere, frontCamera(), style), InputError);
  style = smallStyle();
  style.height = 0;
  EXPECT_THROW(renderMesh(scene.sphere, frontCamera(), style), InputError);

  RenderCamera camera = frontCamera();
  camera.target = camera.eye;
  EXPECT_THROW(renderMesh(scene.sphere, camera, smallStyle()), InputError);
  camera = frontCamera();
  camera.up = Eigen::Vector3d::UnitZ();  // parallel to the view direction
  EXPECT_THROW(renderMesh(scene.sphere, camera, smallStyle()), InputError);

  SurfaceColours short_colours;
  short_colours.per_vertex.resize(3);
  EXPECT_THROW(renderMesh(scene.sphere, frontCamera(), smallStyle(), short_colours), InputError);
  EXPECT_THROW(MeshRenderer(TriangleMesh{}), InputError);
  EXPECT_THROW(regionColours(scene.sphere, {0}, {{0, 1, 1 << 30}}, Eigen::Vector3f::Ones()), InputError);
  EXPECT_THROW(tileImages({}, 2), InputError);
}

TEST(MeshRender, OrbitCamerasFitTheWholeMesh) {
  const TriangleMesh sphere = makeIcosphere(3, 0.05, Eigen::Vector3d(1.0, 2.0, 3.0));
  OrbitParameters params;
  params.count = 5;
  params.top_view = true;
  const auto cameras = orbitCameras(sphere, params);
  ASSERT_EQ(cameras.size(), 5u);
  EXPECT_EQ(cameras[0].name, "front");
  EXPECT_EQ(cameras[1].name, "right");
  EXPECT_EQ(cameras[4].name, "top");
  EXPECT_LT(cameras[0].eye.y(), 2.0);  // the front camera is on the -y side
  EXPECT_GT(cameras[1].eye.x(), 1.0);  // the right camera on the +x side
  RenderStyle style = smallStyle();
  style.samples_per_axis = 1;
  for (const RenderCamera& camera : cameras) {
    const RgbImage image = renderMesh(sphere, camera, style);
    // The image border is background everywhere (mesh fully inside the
    // view), and the centre is the sphere.
    for (int x = 0; x < image.width; ++x) {
      EXPECT_EQ(image.at(x, 0), (Pixel{255, 255, 255})) << camera.name;
      EXPECT_EQ(image.at(x, image.height - 1), (Pixel{255, 255, 255})) << camera.name;
    }
    for (int y = 0; y < image.height; ++y) {
      EXPECT_EQ(image.at(0, y), (Pixel{255, 255, 255})) << camera.name;
      EXPECT_EQ(image.at(image.width - 1, y), (Pixel{255, 255, 255})) << camera.name;
    }
    EXPECT_NE(image.at(80, 60), (Pixel{255, 255, 255})) << camera.name;
    // The sphere spans most of the image height: fitted, not tiny.
    EXPECT_NE(image.at(80, 60 + 45), (Pixel{255, 255, 255})) << camera.name;
  }
}

TEST(MeshRender, TilesAndLegendHaveTheAnnouncedSize) {
  const RgbImage a(10, 20, {1, 2, 3}), b(15, 5, {4, 5, 6});
  const RgbImage tiled = tileImages({a, b, a}, 2);
  EXPECT_EQ(tiled.width, 30);
  EXPECT_EQ(tiled.height, 40);
  EXPECT_EQ(tiled.at(0, 0), (Pixel{1, 2, 3}));
  EXPECT_EQ(tiled.at(15, 0), (Pixel{4, 5, 6}));
  EXPECT_EQ(tiled.at(15, 10), (Pixel{255, 255, 255}));  // below b, in its cell
  EXPECT_EQ(tiled.at(0, 20), (Pixel{1, 2, 3}));
  const std::vector<LegendEntry> legend{{fingerColour(0), "finger 0", false}, {Eigen::Vector3f::Zero(), "contact", true}};
  const RgbImage with = appendLegend(RgbImage(400, 100), legend);
  EXPECT_EQ(with.width, 400);
  EXPECT_EQ(with.height, 100 + legendHeight(400, legend));
  EXPECT_GT(legendHeight(400, legend), 0);
  // A narrow image wraps the legend onto more lines.
  EXPECT_GT(legendHeight(60, legend), legendHeight(400, legend));
}

TEST(MeshRender, ComparisonColoursFollowIntersectionAndInsideFlags) {
  const TriangleMesh sphere = makeIcosphere(2, 1.0);
  std::vector<int> region;
  for (std::size_t v = 0; v < sphere.vertexCount(); ++v)
    if (sphere.vertices.positions[v].z() > 0.5) region.push_back(static_cast<int>(v));
  const Eigen::Vector3f base(0.5f, 0.5f, 0.5f);
  const ComparisonPalette palette;
  // The first region face is intersected, the others are not.
  int first_region_face = -1;
  std::vector<std::uint8_t> in(sphere.vertexCount(), 0);
  for (int v : region) in[static_cast<std::size_t>(v)] = 1;
  for (std::size_t f = 0; f < sphere.faceCount() && first_region_face < 0; ++f) {
    const Triangle& t = sphere.faces[f];
    if (in[static_cast<std::size_t>(t[0])] && in[static_cast<std::size_t>(t[1])] && in[static_cast<std::size_t>(t[2])])
      first_region_face = static_cast<int>(f);
  }
  ASSERT_GE(first_region_face, 0);
  const auto cad = cadComparisonColours(sphere, {region}, {{first_region_face}}, base, palette);
  std::size_t missed = 0, intersected = 0, other = 0;
  for (const auto& c : cad)
    (c == palette.missed ? missed : c == palette.intersection ? intersected : other) += 1;
  EXPECT_EQ(intersected, 1u);
  EXPECT_GT(missed, 0u);
  EXPECT_GT(other, 0u);

  // The reconstructed side per corner: the corners of region triangles at
  // the top vertex are false positives, other region-triangle corners
  // inside, and corners of the other triangles base, even at region vertices.
  std::size_t top = 0;
  for (std::size_t k = 1; k < region.size(); ++k)
    if (sphere.vertices.positions[static_cast<std::size_t>(region[k])].z() >
        sphere.vertices.positions[static_cast<std::size_t>(region[top])].z())
      top = k;
  std::vector<std::uint8_t> inside(region.size(), 1);
  inside[top] = 0;
  const auto scan = scanComparisonColours(sphere, {region}, {inside}, base, palette);
  ASSERT_EQ(scan.size(), 3 * sphere.faceCount());
  std::size_t fp_corners = 0, inside_corners = 0;
  for (std::size_t f = 0; f < sphere.faceCount(); ++f) {
    const Triangle& t = sphere.faces[f];
    const bool region_face =
        in[static_cast<std::size_t>(t[0])] && in[static_cast<std::size_t>(t[1])] && in[static_cast<std::size_t>(t[2])];
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3f& c = scan[3 * f + static_cast<std::size_t>(k)];
      if (!region_face) {
        EXPECT_EQ(c, base);
      } else if (t[k] == region[top]) {
        EXPECT_EQ(c, palette.false_positive);
        ++fp_corners;
      } else {
        EXPECT_EQ(c, palette.intersection);
        ++inside_corners;
      }
    }
  }
  EXPECT_GT(fp_corners, 0u);
  EXPECT_GT(inside_corners, 0u);
}

}  // namespace
}  // namespace icrkit::report
