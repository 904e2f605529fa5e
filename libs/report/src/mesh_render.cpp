#include <icrkit/report/mesh_render.hpp>

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_topology.hpp>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace icrkit::report {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::uint8_t toByte(float value) {
  const float clamped = std::min(1.0f, std::max(0.0f, value));
  return static_cast<std::uint8_t>(std::lround(clamped * 255.0f));
}

std::array<std::uint8_t, 3> toBytes(const Eigen::Vector3f& colour) {
  return {toByte(colour.x()), toByte(colour.y()), toByte(colour.z())};
}

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

// Orthonormal camera frame: forward (into the scene), right, up (in the image).
struct CameraFrame {
  Eigen::Vector3d forward, right, up;
  double tan_half_height = 0.0;  // tan(vertical fov / 2)
};

CameraFrame cameraFrame(const RenderCamera& camera) {
  if (!finite(camera.eye) || !finite(camera.target) || !finite(camera.up))
    throw InputError("camera", camera.name, "eye, target and up must be finite");
  if (!(camera.vertical_fov_rad > 0.0 && camera.vertical_fov_rad < kPi))
    throw InputError("camera", camera.name,
                     "vertical field of view must be in (0, pi) radians, got " + std::to_string(camera.vertical_fov_rad));
  const Eigen::Vector3d view = camera.target - camera.eye;
  // Any non-zero distance will do: scenes may be in millimetres or metres.
  if (!(view.norm() > 0.0)) throw InputError("camera", camera.name, "eye and target coincide");
  CameraFrame frame;
  frame.forward = view.normalized();
  const Eigen::Vector3d side = frame.forward.cross(camera.up);
  if (!(camera.up.norm() > 0.0) || side.norm() <= 1e-9 * camera.up.norm())
    throw InputError("camera", camera.name, "the up vector is zero or parallel to the view direction");
  frame.right = side.normalized();
  frame.up = frame.right.cross(frame.forward);
  frame.tan_half_height = std::tan(0.5 * camera.vertical_fov_rad);
  return frame;
}

void checkStyle(const RenderStyle& style) {
  auto bad = [](const std::string& field, const std::string& detail) {
    throw InputError("render style", field, detail);
  };
  if (style.width < 1 || style.height < 1)
    bad("size", "width and height must be >= 1 pixel, got " + std::to_string(style.width) + "x" +
                    std::to_string(style.height));
  // 2^14 per side keeps width * height * samples^2 far from int overflow.
  if (style.width > 16384 || style.height > 16384)
    bad("size", "width and height must be <= 16384 pixels, got " + std::to_string(style.width) + "x" +
                    std::to_string(style.height));
  if (style.samples_per_axis < 1 || style.samples_per_axis > 8)
    bad("samples_per_axis", "must be in 1..8, got " + std::to_string(style.samples_per_axis));
  if (!(style.marker_depth_tolerance >= 0.0)) bad("marker_depth_tolerance", "must be >= 0");
  if (!style.key_direction_camera.allFinite() || style.key_direction_camera.norm() == 0.0)
    bad("key_direction_camera", "must be a finite, non-zero vector");
}

// Everything one pixel sample needs, shared read-only by the render threads.
struct ShadingInputs {
  const TriangleMesh* mesh;
  const RenderStyle* style;
  const SurfaceColours* colours;
  bool smooth;
  Eigen::Vector3d key_world;
};

Eigen::Vector3f albedo(const ShadingInputs& in, const RayHit& hit) {
  const SurfaceColours& colours = *in.colours;
  const auto f = static_cast<std::size_t>(hit.face);
  if (!colours.per_face.empty()) return colours.per_face[f];
  const bool corners = !colours.per_corner.empty();
  if (!corners && colours.per_vertex.empty()) return in.style->base_colour;
  const Triangle& t = in.mesh->faces[f];
  auto corner = [&](int k) -> const Eigen::Vector3f& {
    return corners ? colours.per_corner[3 * f + static_cast<std::size_t>(k)]
                   : colours.per_vertex[static_cast<std::size_t>(t[k])];
  };
  const double w[3] = {1.0 - hit.u - hit.v, hit.u, hit.v};
  if (colours.vertex_colouring == VertexColouring::Interpolated) {
    Eigen::Vector3f c = Eigen::Vector3f::Zero();
    for (int k = 0; k < 3; ++k) c += static_cast<float>(w[k]) * corner(k);
    return c;
  }
  // The largest barycentric weight: the three parts meet at the centroid
  // and each has a third of the face's area. Ties go to the first corner.
  int nearest = 0;
  for (int k = 1; k < 3; ++k)
    if (w[k] > w[nearest]) nearest = k;
  return corner(nearest);
}

Eigen::Vector3f shade(const ShadingInputs& in, const RayHit& hit, const Eigen::Vector3d& direction) {
  const Eigen::Vector3d to_eye = -direction;
  Eigen::Vector3d face_normal = hit.face_normal;
  const bool back = face_normal.dot(to_eye) < 0.0;
  Eigen::Vector3d normal = face_normal;
  if (in.smooth) {
    const Triangle& t = in.mesh->faces[static_cast<std::size_t>(hit.face)];
    const auto& normals = in.mesh->vertices.normals;
    const Eigen::Vector3d blended = (1.0 - hit.u - hit.v) * normals[static_cast<std::size_t>(t[0])] +
                                    hit.u * normals[static_cast<std::size_t>(t[1])] +
                                    hit.v * normals[static_cast<std::size_t>(t[2])];
    // Vertex normals may disagree with the winding (a mesh whose normals were
    // not oriented): follow the face, which is what the ray saw.
    if (blended.norm() > 1e-12) normal = blended.dot(face_normal) >= 0.0 ? blended.normalized() : -blended.normalized();
  }
  if (back) normal = -normal;  // two-sided: the side the camera sees is lit
  const RenderStyle& style = *in.style;
  const double light = style.ambient + style.headlight * std::max(0.0, normal.dot(to_eye)) +
                       style.key * std::max(0.0, normal.dot(in.key_world));
  return albedo(in, hit) * static_cast<float>(light);
}

void checkColours(const TriangleMesh& mesh, const SurfaceColours& colours) {
  if (!colours.per_face.empty() && colours.per_face.size() != mesh.faceCount())
    throw InputError("colours", "per face",
                     std::to_string(colours.per_face.size()) + " colours for " + std::to_string(mesh.faceCount()) +
                         " faces");
  if (!colours.per_corner.empty() && colours.per_corner.size() != 3 * mesh.faceCount())
    throw InputError("colours", "per corner",
                     std::to_string(colours.per_corner.size()) + " colours for " + std::to_string(mesh.faceCount()) +
                         " faces (3 each)");
  if (!colours.per_vertex.empty() && colours.per_vertex.size() != mesh.vertexCount())
    throw InputError("colours", "per vertex",
                     std::to_string(colours.per_vertex.size()) + " colours for " +
                         std::to_string(mesh.vertexCount()) + " vertices");
}

// Blends an anti-aliased disc with an outline ring into a float RGB buffer.
void drawDisc(std::vector<float>& buffer, int width, int height, double cx, double cy, const Marker& marker) {
  const double inner = marker.radius_px;
  const double outer = marker.radius_px + std::max(0.0, marker.outline_px);
  const int x0 = std::max(0, static_cast<int>(std::floor(cx - outer - 1.0)));
  const int x1 = std::min(width - 1, static_cast<int>(std::ceil(cx + outer + 1.0)));
  const int y0 = std::max(0, static_cast<int>(std::floor(cy - outer - 1.0)));
  const int y1 = std::min(height - 1, static_cast<int>(std::ceil(cy + outer + 1.0)));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
      // Coverage by distance from the edge: a one-pixel linear ramp.
      const float all = static_cast<float>(std::clamp(outer + 0.5 - d, 0.0, 1.0));
      const float fill = static_cast<float>(std::clamp(inner + 0.5 - d, 0.0, 1.0));
      if (all <= 0.0f) continue;
      float* p = &buffer[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 3];
      for (int c = 0; c < 3; ++c)
        p[c] = p[c] * (1.0f - all) + marker.colour[c] * fill + marker.outline_colour[c] * (all - fill);
    }
}

cv::Mat wrap(RgbImage& image) { return cv::Mat(image.height, image.width, CV_8UC3, image.rgb.data()); }

// The memory holds RGB; OpenCV drawing only needs the scalar in the same order.
cv::Scalar scalar(const Eigen::Vector3f& colour) {
  const auto b = toBytes(colour);
  return cv::Scalar(b[0], b[1], b[2]);
}

// Legend layout, shared by appendLegend and legendHeight.
constexpr int kLegendLine = 26;      // pixels per line
constexpr int kLegendPad = 8;        // above, below and at the left
constexpr int kSwatch = 14;          // square side / disc diameter
constexpr double kLegendFont = 0.5;  // cv::FONT_HERSHEY_SIMPLEX scale

struct LegendPlacement {
  int x = 0;
  int line = 0;
};

std::vector<LegendPlacement> layOutLegend(int width, const std::vector<LegendEntry>& entries, int& lines) {
  std::vector<LegendPlacement> placements;
  int x = kLegendPad;
  int line = 0;
  for (const LegendEntry& entry : entries) {
    int baseline = 0;
    const int text = cv::getTextSize(entry.label, cv::FONT_HERSHEY_SIMPLEX, kLegendFont, 1, &baseline).width;
    const int span = kSwatch + 6 + text;
    if (x > kLegendPad && x + span > width - kLegendPad) {
      x = kLegendPad;
      ++line;
    }
    placements.push_back({x, line});
    x += span + 18;
  }
  lines = entries.empty() ? 0 : line + 1;
  return placements;
}

}  // namespace

// --- Images ----------------------------------------------------------------

RgbImage::RgbImage(int w, int h, const std::array<std::uint8_t, 3>& fill) : width(w), height(h) {
  if (w < 0 || h < 0) throw std::invalid_argument("RgbImage: negative size");
  rgb.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
  for (std::size_t i = 0; i < rgb.size(); i += 3) std::copy(fill.begin(), fill.end(), rgb.begin() + static_cast<std::ptrdiff_t>(i));
}

std::array<std::uint8_t, 3> RgbImage::at(int x, int y) const {
  if (x < 0 || y < 0 || x >= width || y >= height) throw std::out_of_range("RgbImage::at: pixel outside the image");
  const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 3;
  return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

void RgbImage::set(int x, int y, const std::array<std::uint8_t, 3>& colour) {
  if (x < 0 || y < 0 || x >= width || y >= height) throw std::out_of_range("RgbImage::set: pixel outside the image");
  const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 3;
  std::copy(colour.begin(), colour.end(), rgb.begin() + static_cast<std::ptrdiff_t>(i));
}

// --- Cameras ---------------------------------------------------------------

BoundingSphere boundingSphere(const TriangleMesh& mesh) {
  // The surface is what is drawn: stray vertices no face uses must not move
  // or widen the views (a point cloud, without faces, is framed whole).
  const std::vector<Eigen::Vector3d> points = mesh.faces.empty() ? mesh.vertices.positions : referencedPositions(mesh);
  if (points.empty()) throw InputError("mesh", "", "has no vertices to frame");
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& p : points) box.extend(p);
  BoundingSphere sphere;
  sphere.centre = box.center();
  for (const Eigen::Vector3d& p : points) sphere.radius = std::max(sphere.radius, (p - sphere.centre).norm());
  return sphere;
}

RenderCamera fittedCamera(const BoundingSphere& sphere, const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                          const Eigen::Vector3d& up, double aspect, double margin) {
  if (!(aspect > 0.0) || !std::isfinite(aspect)) throw InputError("camera", "aspect", "must be > 0");
  if (!(margin > 0.0) || !std::isfinite(margin)) throw InputError("camera", "margin", "must be > 0");
  RenderCamera camera;
  camera.eye = eye;
  camera.target = target;
  camera.up = up;
  camera.vertical_fov_rad = kPi / 2.0;
  const double distance = (sphere.centre - eye).norm();
  const double radius = sphere.radius * margin;
  if (distance > radius && radius > 0.0) {
    // The sphere's angular radius seen from the eye must fit into half of the
    // narrower extent; the target may be off-centre, so add that angle too.
    const double angular = std::asin(radius / distance);
    const Eigen::Vector3d to_target = target - eye, to_centre = sphere.centre - eye;
    const double offset = to_target.norm() > 0.0
                              ? std::acos(std::clamp(to_target.normalized().dot(to_centre.normalized()), -1.0, 1.0))
                              : 0.0;
    const double half = std::min(angular + offset, kPi / 2.0 - 1e-3);
    double tan_half_height = std::tan(half);
    if (aspect < 1.0) tan_half_height /= aspect;  // the width is the narrower extent
    camera.vertical_fov_rad = std::min(2.0 * std::atan(tan_half_height), kPi - 1e-3);
  }
  cameraFrame(camera);  // validates eye != target and up
  return camera;
}

std::vector<RenderCamera> orbitCameras(const TriangleMesh& mesh, const OrbitParameters& params) {
  if (params.count < 1 || params.count > 64)
    throw InputError("views", "", "the number of views must be in 1..64, got " + std::to_string(params.count));
  if (!(params.vertical_fov_rad > 0.0 && params.vertical_fov_rad < kPi))
    throw InputError("views", "vertical_fov_rad", "must be in (0, pi)");
  if (!(params.elevation_rad > -kPi / 2.0 && params.elevation_rad < kPi / 2.0))
    throw InputError("views", "elevation_rad", "must be in (-pi/2, pi/2)");
  if (!(params.aspect > 0.0) || !(params.margin > 0.0))
    throw InputError("views", "", "aspect and margin must be > 0");
  if (!params.up.allFinite() || params.up.norm() == 0.0) throw InputError("views", "up", "must be a non-zero vector");

  const BoundingSphere sphere = boundingSphere(mesh);
  const Eigen::Vector3d up = params.up.normalized();
  // A horizontal "front" axis: -y projected onto the plane normal to up
  // (or -x when up is along y).
  Eigen::Vector3d front = -Eigen::Vector3d::UnitY() + up * up.y();
  if (front.norm() < 1e-6) front = -Eigen::Vector3d::UnitX() + up * up.x();
  front.normalize();
  // The image's right in the front view (+x for up = +z, front = -y).
  const Eigen::Vector3d side = up.cross(front).normalized();

  // Distance at which the sphere (times margin) fits the narrower extent.
  const double tan_half_height = std::tan(0.5 * params.vertical_fov_rad);
  const double tan_half_narrow = std::min(tan_half_height, tan_half_height * params.aspect);
  const double radius = std::max(sphere.radius, 1e-9) * params.margin;
  const double distance = radius / std::sin(std::atan(tan_half_narrow));

  const bool top = params.top_view && params.count >= 2;
  const int ring = top ? params.count - 1 : params.count;
  static const char* const kSideNames[4] = {"front", "right", "back", "left"};
  std::vector<RenderCamera> cameras;
  for (int k = 0; k < ring; ++k) {
    const double azimuth = 2.0 * kPi * k / ring;
    // From the front towards `side`: in a ring of four the second camera
    // looks at the side that is on the right in the front view.
    const Eigen::Vector3d horizontal = std::cos(azimuth) * front + std::sin(azimuth) * side;
    const Eigen::Vector3d direction =
        std::cos(params.elevation_rad) * horizontal + std::sin(params.elevation_rad) * up;
    RenderCamera camera;
    camera.eye = sphere.centre + distance * direction;
    camera.target = sphere.centre;
    camera.up = up;
    camera.vertical_fov_rad = params.vertical_fov_rad;
    // Quarter turns get their side's name, other azimuths their angle.
    camera.name = (4 * k) % ring == 0 ? kSideNames[(4 * k) / ring]
                                      : "azimuth " + std::to_string(static_cast<int>(std::lround(azimuth * 180.0 / kPi)));
    cameras.push_back(camera);
  }
  if (top) {
    RenderCamera camera;
    camera.eye = sphere.centre + distance * up;
    camera.target = sphere.centre;
    camera.up = -front;  // the front of the object at the bottom of the image
    camera.vertical_fov_rad = params.vertical_fov_rad;
    camera.name = "top";
    cameras.push_back(camera);
  }
  return cameras;
}

// --- Rendering ---------------------------------------------------------------

namespace {
RayCaster makeCaster(const TriangleMesh& mesh) {
  if (mesh.faceCount() == 0) throw InputError("mesh", "", "has no faces to render");
  try {
    mesh.validate();
    return RayCaster(mesh);
  } catch (const std::invalid_argument& error) {
    throw InputError("mesh", "", error.what());
  }
}
}  // namespace

MeshRenderer::MeshRenderer(const TriangleMesh& mesh)
    : mesh_(&mesh), caster_(makeCaster(mesh)), sphere_(boundingSphere(mesh)) {}

RgbImage MeshRenderer::render(const RenderCamera& camera, const RenderStyle& style, const SurfaceColours& colours,
                              const std::vector<Marker>& markers) const {
  checkStyle(style);
  const CameraFrame frame = cameraFrame(camera);
  checkColours(*mesh_, colours);
  for (std::size_t i = 0; i < markers.size(); ++i)
    if (!markers[i].position.allFinite() || !(markers[i].radius_px > 0.0) || !std::isfinite(markers[i].radius_px))
      throw InputError("markers", "marker " + std::to_string(i), "needs a finite position and a radius > 0");

  const Eigen::Vector3d key_camera = style.key_direction_camera.normalized();
  const ShadingInputs inputs{mesh_, &style, &colours, style.smooth_shading && mesh_->vertices.hasNormals(),
                             (key_camera.x() * frame.right + key_camera.y() * frame.up - key_camera.z() * frame.forward)
                                 .normalized()};

  const int width = style.width, height = style.height, k = style.samples_per_axis;
  const double aspect = static_cast<double>(width) / height;
  const double sx = frame.tan_half_height * aspect, sy = frame.tan_half_height;
  std::vector<float> buffer(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);

  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = 0; x < width; ++x) {
        Eigen::Vector3f sum = Eigen::Vector3f::Zero();
        for (int j = 0; j < k; ++j)
          for (int i = 0; i < k; ++i) {
            // Sample centres on a regular k x k grid inside the pixel.
            const double ndc_x = 2.0 * (x + (i + 0.5) / k) / width - 1.0;
            const double ndc_y = 1.0 - 2.0 * (y + (j + 0.5) / k) / height;
            Ray ray;
            ray.origin = camera.eye;
            ray.direction = (frame.forward + ndc_x * sx * frame.right + ndc_y * sy * frame.up).normalized();
            const RayHit hit = caster_.closestHit(ray);
            sum += hit.hit ? shade(inputs, hit, ray.direction) : style.background;
          }
        sum /= static_cast<float>(k * k);
        float* p = &buffer[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 3];
        for (int c = 0; c < 3; ++c) p[c] = sum[c];
      }
  });

  const double tolerance = style.marker_depth_tolerance * sphere_.radius;
  for (const Marker& marker : markers) {
    const Eigen::Vector3d offset = marker.position - camera.eye;
    const double depth = offset.dot(frame.forward);
    if (!(depth > 0.0)) continue;  // behind the camera
    const double distance = offset.norm();
    Ray ray;
    ray.origin = camera.eye;
    ray.direction = offset / distance;
    const RayHit hit = caster_.closestHit(ray);
    if (hit.hit && hit.distance < distance - tolerance) continue;  // hidden by the surface
    const double ndc_x = offset.dot(frame.right) / depth / sx;
    const double ndc_y = offset.dot(frame.up) / depth / sy;
    drawDisc(buffer, width, height, (ndc_x + 1.0) * 0.5 * width, (1.0 - ndc_y) * 0.5 * height, marker);
  }

  RgbImage image(width, height);
  for (std::size_t i = 0; i < buffer.size(); ++i) image.rgb[i] = toByte(buffer[i]);
  return image;
}

RgbImage renderMesh(const TriangleMesh& mesh, const RenderCamera& camera, const RenderStyle& style,
                    const SurfaceColours& colours, const std::vector<Marker>& markers) {
  return MeshRenderer(mesh).render(camera, style, colours, markers);
}

// --- Layout ------------------------------------------------------------------

void drawCaption(RgbImage& image, const std::string& caption) {
  if (caption.empty() || image.width == 0 || image.height == 0) return;
  cv::Mat mat = wrap(image);
  const double scale = std::clamp(image.height / 1000.0, 0.4, 1.2);
  const int thickness = scale > 0.8 ? 2 : 1;
  int baseline = 0;
  const cv::Size size = cv::getTextSize(caption, cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &baseline);
  const int pad = 4;
  const cv::Rect box = cv::Rect(0, 0, size.width + 2 * pad + 4, size.height + baseline + 2 * pad) &
                       cv::Rect(0, 0, image.width, image.height);
  mat(box) = cv::Scalar(245, 245, 245);
  cv::putText(mat, caption, cv::Point(pad + 2, pad + size.height), cv::FONT_HERSHEY_SIMPLEX, scale,
              cv::Scalar(20, 20, 20), thickness, cv::LINE_AA);
}

RgbImage tileImages(const std::vector<RgbImage>& images, int columns, const std::array<std::uint8_t, 3>& fill) {
  if (images.empty()) throw InputError("tiles", "", "no images to tile");
  if (columns < 1) throw InputError("tiles", "columns", "must be >= 1, got " + std::to_string(columns));
  int cell_w = 0, cell_h = 0;
  for (const RgbImage& image : images) {
    cell_w = std::max(cell_w, image.width);
    cell_h = std::max(cell_h, image.height);
  }
  const int count = static_cast<int>(images.size());
  const int cols = std::min(columns, count);
  const int rows = (count + cols - 1) / cols;
  RgbImage out(cols * cell_w, rows * cell_h, fill);
  for (int i = 0; i < count; ++i) {
    const RgbImage& image = images[static_cast<std::size_t>(i)];
    const int ox = (i % cols) * cell_w, oy = (i / cols) * cell_h;
    for (int y = 0; y < image.height; ++y)
      std::copy_n(image.rgb.begin() + static_cast<std::ptrdiff_t>(y) * image.width * 3, image.width * 3,
                  out.rgb.begin() + (static_cast<std::ptrdiff_t>(oy + y) * out.width + ox) * 3);
  }
  return out;
}

int legendHeight(int width, const std::vector<LegendEntry>& entries) {
  int lines = 0;
  layOutLegend(width, entries, lines);
  return lines == 0 ? 0 : lines * kLegendLine + 2 * kLegendPad;
}

RgbImage appendLegend(const RgbImage& image, const std::vector<LegendEntry>& entries) {
  const int strip = legendHeight(image.width, entries);
  if (strip == 0) return image;
  RgbImage out(image.width, image.height + strip);
  std::copy(image.rgb.begin(), image.rgb.end(), out.rgb.begin());
  cv::Mat mat = wrap(out);
  int lines = 0;
  const std::vector<LegendPlacement> placements = layOutLegend(image.width, entries, lines);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const LegendEntry& entry = entries[i];
    const int top = image.height + kLegendPad + placements[i].line * kLegendLine + (kLegendLine - kSwatch) / 2;
    const int x = placements[i].x;
    if (entry.dot) {
      const cv::Point centre(x + kSwatch / 2, top + kSwatch / 2);
      cv::circle(mat, centre, kSwatch / 2, cv::Scalar(40, 40, 40), cv::FILLED, cv::LINE_AA);
      cv::circle(mat, centre, kSwatch / 2 - 2, scalar(entry.colour), cv::FILLED, cv::LINE_AA);
    } else {
      cv::rectangle(mat, cv::Rect(x, top, kSwatch, kSwatch), scalar(entry.colour), cv::FILLED);
      cv::rectangle(mat, cv::Rect(x, top, kSwatch, kSwatch), cv::Scalar(40, 40, 40), 1);
    }
    cv::putText(mat, entry.label, cv::Point(x + kSwatch + 6, top + kSwatch - 2), cv::FONT_HERSHEY_SIMPLEX,
                kLegendFont, cv::Scalar(20, 20, 20), 1, cv::LINE_AA);
  }
  return out;
}

std::string encodePng(const RgbImage& image) {
  if (image.width < 1 || image.height < 1) throw InputError("image", "", "an empty image has no PNG");
  cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.rgb.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  std::vector<std::uint8_t> bytes;
  if (!cv::imencode(".png", bgr, bytes, {cv::IMWRITE_PNG_COMPRESSION, 6}))
    throw std::runtime_error("encodePng: OpenCV could not encode the image");
  return std::string(bytes.begin(), bytes.end());
}

void writePng(const std::string& path, const RgbImage& image) {
  const std::string bytes = encodePng(image);
  writeFileAtomically(path, [&bytes](std::ostream& out) { out.write(bytes.data(), static_cast<std::streamsize>(bytes.size())); });
}

// --- ICR colouring ---------------------------------------------------------

Eigen::Vector3f fingerColour(int finger) {
  static const std::array<std::array<int, 3>, 7> kOkabeIto{{{230, 159, 0},
                                                            {86, 180, 233},
                                                            {0, 158, 115},
                                                            {204, 121, 167},
                                                            {0, 114, 178},
                                                            {240, 228, 66},
                                                            {213, 94, 0}}};
  if (finger < 0) throw InputError("finger", "", "finger index must be >= 0, got " + std::to_string(finger));
  const auto& c = kOkabeIto[static_cast<std::size_t>(finger) % kOkabeIto.size()];
  return Eigen::Vector3f(c[0], c[1], c[2]) / 255.0f;
}

namespace {
void checkVertex(const TriangleMesh& mesh, int v, const std::string& source, const std::string& location) {
  if (v < 0 || static_cast<std::size_t>(v) >= mesh.vertexCount())
    throw InputError(source, location,
                     "vertex " + std::to_string(v) + " is out of range: expected 0.." +
                         std::to_string(static_cast<long long>(mesh.vertexCount()) - 1));
}
}  // namespace

std::vector<Eigen::Vector3f> regionColours(const TriangleMesh& mesh, const std::vector<int>& fingers,
                                           const std::vector<std::vector<int>>& regions,
                                           const Eigen::Vector3f& base) {
  if (fingers.size() != regions.size())
    throw InputError("region", "", "one finger index per region needed");
  std::vector<int> owner(mesh.vertexCount(), -1);
  for (std::size_t r = 0; r < regions.size(); ++r)
    for (std::size_t k = 0; k < regions[r].size(); ++k) {
      const int v = regions[r][k];
      checkVertex(mesh, v, "region", "finger " + std::to_string(fingers[r]) + ", element " + std::to_string(k));
      int& o = owner[static_cast<std::size_t>(v)];
      if (o < 0 || fingers[r] < o) o = fingers[r];
    }
  std::vector<Eigen::Vector3f> colours(mesh.vertexCount(), base);
  for (std::size_t v = 0; v < owner.size(); ++v)
    if (owner[v] >= 0) colours[v] = fingerColour(owner[v]);
  return colours;
}

std::vector<Eigen::Vector3f> cadComparisonColours(const TriangleMesh& cad,
                                                  const std::vector<std::vector<int>>& cad_regions,
                                                  const std::vector<std::vector<int>>& intersection_faces,
                                                  const Eigen::Vector3f& base, const ComparisonPalette& palette) {
  std::vector<Eigen::Vector3f> colours(cad.faceCount(), base);
  for (std::size_t r = 0; r < cad_regions.size(); ++r) {
    std::vector<std::uint8_t> in(cad.vertexCount(), 0);
    for (std::size_t k = 0; k < cad_regions[r].size(); ++k) {
      checkVertex(cad, cad_regions[r][k], "CAD region", "region " + std::to_string(r) + ", element " + std::to_string(k));
      in[static_cast<std::size_t>(cad_regions[r][k])] = 1;
    }
    for (std::size_t f = 0; f < cad.faceCount(); ++f) {
      const Triangle& t = cad.faces[f];
      if (in[static_cast<std::size_t>(t[0])] && in[static_cast<std::size_t>(t[1])] && in[static_cast<std::size_t>(t[2])])
        colours[f] = palette.missed;
    }
  }
  for (std::size_t r = 0; r < intersection_faces.size(); ++r)
    for (std::size_t k = 0; k < intersection_faces[r].size(); ++k) {
      const int f = intersection_faces[r][k];
      if (f < 0 || static_cast<std::size_t>(f) >= cad.faceCount())
        throw InputError("intersection", "region " + std::to_string(r) + ", element " + std::to_string(k),
                         "face " + std::to_string(f) + " is out of range");
      colours[static_cast<std::size_t>(f)] = palette.intersection;
    }
  return colours;
}

std::vector<Eigen::Vector3f> scanComparisonColours(const TriangleMesh& scan,
                                                   const std::vector<std::vector<int>>& scan_regions,
                                                   const std::vector<std::vector<std::uint8_t>>& inside,
                                                   const Eigen::Vector3f& base, const ComparisonPalette& palette) {
  if (inside.size() != scan_regions.size())
    throw InputError("reconstructed region", "", "one inside-flag list per region needed");
  // Per corner: 0 base, 1 false positive, 2 inside; the maximum over regions wins.
  std::vector<std::uint8_t> state(3 * scan.faceCount(), 0);
  std::vector<int> verdict(scan.vertexCount(), -1);  // this region's flag per vertex, -1: not in it
  for (std::size_t r = 0; r < scan_regions.size(); ++r) {
    if (inside[r].size() != scan_regions[r].size())
      throw InputError("reconstructed region", "region " + std::to_string(r),
                       "one inside flag per region vertex needed");
    std::fill(verdict.begin(), verdict.end(), -1);
    for (std::size_t k = 0; k < scan_regions[r].size(); ++k) {
      const int v = scan_regions[r][k];
      checkVertex(scan, v, "reconstructed region", "region " + std::to_string(r) + ", element " + std::to_string(k));
      int& flag = verdict[static_cast<std::size_t>(v)];
      flag = std::max(flag, inside[r][k] ? 1 : 0);  // a duplicate listed inside once counts as inside
    }
    for (std::size_t f = 0; f < scan.faceCount(); ++f) {
      const Triangle& t = scan.faces[f];
      const int a = verdict[static_cast<std::size_t>(t[0])], b = verdict[static_cast<std::size_t>(t[1])],
                c = verdict[static_cast<std::size_t>(t[2])];
      if (a < 0 || b < 0 || c < 0) continue;  // not a region triangle: carries no region area
      const int flags[3] = {a, b, c};
      for (int k = 0; k < 3; ++k) {
        auto& s = state[3 * f + static_cast<std::size_t>(k)];
        s = std::max<std::uint8_t>(s, flags[k] ? 2 : 1);
      }
    }
  }
  std::vector<Eigen::Vector3f> colours(state.size(), base);
  for (std::size_t i = 0; i < state.size(); ++i)
    if (state[i] == 1)
      colours[i] = palette.false_positive;
    else if (state[i] == 2)
      colours[i] = palette.intersection;
  return colours;
}

}  // namespace icrkit::report
