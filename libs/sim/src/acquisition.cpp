#include <icrkit/sim/acquisition.hpp>

#include <icrkit/core/error.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <random>

namespace icrkit::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The optical frame (x right, y down, z forward) at `eye` looking at
// `target`, with the image's up direction as close to +z as possible.
Eigen::Isometry3d lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d forward = (target - eye).normalized();
  Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ());
  // Looking straight down or up: any right will do, +x keeps it defined.
  if (right.squaredNorm() < 1e-12) right = Eigen::Vector3d::UnitX();
  right.normalize();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear().col(0) = right;
  pose.linear().col(1) = down;
  pose.linear().col(2) = forward;
  pose.translation() = eye;
  return pose;
}

Eigen::Vector3d randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::Vector3d v;
  do v = Eigen::Vector3d(g(rng), g(rng), g(rng));
  while (v.squaredNorm() < 1e-12);
  return v.normalized();
}

Eigen::Isometry3d motion(const Eigen::Vector3d& translation, const Eigen::Vector3d& rotation_vector) {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  const double angle = rotation_vector.norm();
  if (angle > 0) m.linear() = Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix();
  m.translation() = translation;
  return m;
}

// Appends an axis-aligned box, faces wound outwards; returns the index of
// its first face. Its top face (+z) is faces first+2 and first+3.
std::size_t appendBox(TriangleMesh& mesh, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const int base = static_cast<int>(mesh.vertices.positions.size());
  for (int k = 0; k < 8; ++k)
    mesh.vertices.positions.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
  const std::size_t first = mesh.faces.size();
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  // Order: bottom (-z), top (+z), -y, +y, -x, +x.
  for (const auto& q : quads) {
    mesh.faces.emplace_back(base + q[0], base + q[1], base + q[2]);
    mesh.faces.emplace_back(base + q[0], base + q[2], base + q[3]);
  }
  return first;
}

// A vertical prism of `sides` sides approximating a cylinder (post).
void appendPrism(TriangleMesh& mesh, double radius, double z0, double z1, int sides) {
  const int base = static_cast<int>(mesh.vertices.positions.size());
  for (int k = 0; k < sides; ++k) {
    const double a = 2.0 * kPi * k / sides;
    mesh.vertices.positions.emplace_back(radius * std::cos(a), radius * std::sin(a), z0);
    mesh.vertices.positions.emplace_back(radius * std::cos(a), radius * std::sin(a), z1);
  }
  const int bottom = base + 2 * sides, top = bottom + 1;
  mesh.vertices.positions.emplace_back(0, 0, z0);
  mesh.vertices.positions.emplace_back(0, 0, z1);
  for (int k = 0; k < sides; ++k) {
    const int a0 = base + 2 * k, a1 = a0 + 1, b0 = base + 2 * ((k + 1) % sides), b1 = b0 + 1;
    mesh.faces.emplace_back(a0, b0, b1);
    mesh.faces.emplace_back(a0, b1, a1);
    mesh.faces.emplace_back(bottom, b0, a0);
    mesh.faces.emplace_back(top, a1, b1);
  }
}

}  // namespace

Setup parseSetup(const std::string& name) {
  std::string upper = name;
  std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return std::toupper(c); });
  if (upper == "A") return Setup::A;
  if (upper == "B") return Setup::B;
  throw InputError("setup name", "", "unknown setup '" + name + "', expected A (SR4000 on an arm around the object) or "
                                  "B (fixed Kinect, object turned on the flange)");
}

std::string setupName(Setup setup) { return setup == Setup::A ? "A" : "B"; }

PoseErrorModel armPoseErrors() { return PoseErrorModel{}; }

PoseErrorModel mobilePoseErrors() {
  PoseErrorModel mobile = independentPoseErrors(0.003, 0.5 * kPi / 180.0);
  mobile.name = "mobile";
  return mobile;
}

PoseErrorModel independentPoseErrors(double sigma_translation, double sigma_rotation) {
  for (const double sigma : {sigma_translation, sigma_rotation})
    if (!std::isfinite(sigma) || sigma < 0)
      throw InputError("pose error model", "", "expected finite sigmas >= 0, got " + std::to_string(sigma));
  PoseErrorModel model = perfectPoses();
  model.name = "custom";
  model.noise_translation = sigma_translation;
  model.noise_rotation = sigma_rotation;
  return model;
}

PoseErrorModel perfectPoses() {
  PoseErrorModel none;
  none.name = "none";
  none.noise_translation = none.noise_rotation = 0.0;
  none.hand_eye_translation = none.hand_eye_rotation = 0.0;
  none.drift_translation = none.drift_rotation = 0.0;
  return none;
}

PoseErrorModel parsePoseErrorModel(const std::string& text, const std::string& source) {
  std::string lower = text;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  if (lower == "arm") return armPoseErrors();
  if (lower == "mobile") return mobilePoseErrors();
  if (lower == "none") return perfectPoses();
  const std::string expected = "expected arm, mobile, none or per-view sigmas T,R with units (T in mm, cm or m, "
                               "R in deg, mrad or rad, e.g. 5mm,1deg), got '" + text + "'";
  const std::size_t comma = lower.find(',');
  if (comma == std::string::npos || lower.find(',', comma + 1) != std::string::npos)
    throw InputError(source, "", expected);
  // A value is a number followed by one of its units: a bare number would
  // leave 5 (mm? m?) to a guess.
  struct Unit {
    const char* suffix;
    double scale;
  };
  auto value = [&](const std::string& item, std::initializer_list<Unit> units) {
    if (item.empty() || !(std::isdigit(static_cast<unsigned char>(item[0])) || item[0] == '.' || item[0] == '-' ||
                          item[0] == '+'))
      throw InputError(source, "", expected);
    char* end = nullptr;
    const double number = std::strtod(item.c_str(), &end);
    const std::string suffix(end);
    for (const Unit& u : units)
      if (suffix == u.suffix) {
        if (!std::isfinite(number)) break;
        if (number < 0) throw InputError(source, "", "expected sigmas >= 0, got '" + item + "' in '" + text + "'");
        return number * u.scale;
      }
    throw InputError(source, "", expected);
  };
  const double translation = value(lower.substr(0, comma), {{"mm", 1e-3}, {"cm", 1e-2}, {"m", 1.0}});
  const double rotation = value(lower.substr(comma + 1), {{"deg", kPi / 180.0}, {"mrad", 1e-3}, {"rad", 1.0}});
  return independentPoseErrors(translation, rotation);
}

std::vector<View> planViews(const AcquisitionParameters& params, const Eigen::AlignedBox3d& object_bounds) {
  if (params.views <= 0)
    throw InputError("AcquisitionParameters::views", "", "expected at least one view, got " + std::to_string(params.views));
  if (params.distance && !(std::isfinite(*params.distance) && *params.distance > 0))
    throw InputError("AcquisitionParameters::distance", "",
                     "expected a finite distance > 0 m (or unset: the setup's default)");
  if (object_bounds.isEmpty()) throw InputError("object", "", "the object has no vertices");
  const double distance = params.distance.value_or(params.setup == Setup::A ? 0.6 : 0.7);
  const Eigen::Vector3d centre = object_bounds.center();
  const PoseErrorModel& e = params.errors;
  for (const double size : {e.noise_translation, e.noise_rotation, e.hand_eye_translation, e.hand_eye_rotation,
                            e.drift_translation, e.drift_rotation})
    if (!std::isfinite(size) || size < 0)
      throw InputError("pose errors", "", "expected finite error sizes >= 0 (model '" + e.name + "')");

  // Fixed errors first, then per-view ones, all from one seeded stream in a
  // fixed order: the same seed gives the same poses. Every model draws the
  // same numbers (a zero-sized error still takes its draws), so the views'
  // noise stays where it is in the stream whichever model is chosen.
  std::mt19937_64 rng(params.seed);
  const Eigen::Isometry3d hand_eye =
      motion(e.hand_eye_translation * randomUnit(rng), e.hand_eye_rotation * randomUnit(rng));
  const Eigen::Vector3d drift_direction = randomUnit(rng), drift_axis = randomUnit(rng);
  std::normal_distribution<double> gauss(0.0, 1.0);

  const double golden_angle = kPi * (3.0 - std::sqrt(5.0));
  std::vector<View> views(static_cast<std::size_t>(params.views));
  for (int k = 0; k < params.views; ++k) {
    double azimuth, elevation;
    if (params.setup == Setup::A) {
      // A spiral over the partial sphere: even coverage for any view count.
      const double t = (k + 0.5) / params.views;
      elevation = params.min_elevation + t * (params.max_elevation - params.min_elevation);
      azimuth = golden_angle * k;
    } else {
      elevation = params.elevation;
      azimuth = 2.0 * kPi * k / params.views;
    }
    const Eigen::Vector3d eye =
        centre + distance * Eigen::Vector3d(std::cos(elevation) * std::cos(azimuth),
                                            std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
    View& view = views[static_cast<std::size_t>(k)];
    view.true_camera = lookAt(eye, centre);
    const Eigen::Vector3d noise_t(gauss(rng), gauss(rng), gauss(rng));
    const Eigen::Vector3d noise_r(gauss(rng), gauss(rng), gauss(rng));
    const Eigen::Isometry3d drift = motion(k * e.drift_translation * drift_direction, k * e.drift_rotation * drift_axis);
    const Eigen::Isometry3d noise = motion(e.noise_translation * noise_t, e.noise_rotation * noise_r);
    view.reported_camera = view.true_camera * hand_eye * drift * noise;
    // An arm needs about 2 s between views; a turning flange about 1 s.
    view.timestamp = (params.setup == Setup::A ? 2.0 : 1.0) * k;
  }
  return views;
}

Scene buildScene(const TriangleMesh& object, Setup setup) {
  Scene scene;
  scene.mesh.vertices.positions = object.vertices.positions;
  scene.mesh.faces = object.faces;
  scene.object_faces = object.faces.size();
  const Eigen::AlignedBox3d bounds = object.vertices.bounds();
  const double footprint = std::max(bounds.sizes().x(), bounds.sizes().y());
  // Fixtures stop 0.1 mm below the object's lowest point: coincident
  // surfaces would make the first hit along a ray ambiguous.
  const double top = bounds.min().z() - 1e-4;
  std::size_t checker_begin = 0, checker_end = 0;
  if (setup == Setup::A) {
    appendBox(scene.mesh, Eigen::Vector3d(-0.4, -0.4, top - 0.02), Eigen::Vector3d(0.4, 0.4, top));
  } else {
    const double half = std::max(0.06, 0.75 * footprint);
    const std::size_t plate = appendBox(scene.mesh, Eigen::Vector3d(-half, -half, top - 0.01), Eigen::Vector3d(half, half, top));
    checker_begin = plate + 2;
    checker_end = plate + 4;
    appendPrism(scene.mesh, 0.02, top - 0.16, top - 0.01, 24);
  }
  const std::size_t object_faces = scene.object_faces;
  scene.appearance.colour = [=](int face, const Eigen::Vector3d& p) -> Colour {
    const auto f = static_cast<std::size_t>(face);
    if (f < object_faces) return {200, 200, 190};  // light, matte object
    if (f >= checker_begin && f < checker_end) {
      // 2 cm squares: the target an RGB-D pipeline detects and removes.
      const long i = static_cast<long>(std::floor(p.x() / 0.02)), j = static_cast<long>(std::floor(p.y() / 0.02));
      return ((i + j) & 1) ? Colour{20, 20, 20} : Colour{235, 235, 235};
    }
    return setup == Setup::A ? Colour{150, 120, 90} : Colour{90, 90, 95};  // wooden table; metal post
  };
  scene.appearance.reflectivity = [=](int face, const Eigen::Vector3d& p) -> double {
    const auto f = static_cast<std::size_t>(face);
    if (f < object_faces) return 0.6;
    if (f >= checker_begin && f < checker_end) {
      const long i = static_cast<long>(std::floor(p.x() / 0.02)), j = static_cast<long>(std::floor(p.y() / 0.02));
      return ((i + j) & 1) ? 0.1 : 0.8;
    }
    return setup == Setup::A ? 0.4 : 0.3;
  };
  return scene;
}

}  // namespace icrkit::sim
