#include <icrkit/core/ray_caster.hpp>
#include <icrkit/core/morton_order.hpp>
#include <icrkit/core/triangle_distance.hpp>

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace icrkit {
namespace {

// Embree reports errors through a callback and a per-thread error code; the
// callback runs on the thread whose API call failed, so a thread-local slot
// carries the message to the check that follows that call without any
// sharing between threads.
thread_local std::string t_embree_message;

const char* errorName(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_UNKNOWN: return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
  }
  return "unrecognised error";
}

void recordEmbreeError(void* /*user*/, RTCError code, const char* message) {
  t_embree_message = std::string(errorName(code)) + (message ? std::string(": ") + message : std::string());
}

void throwOnEmbreeError(RTCDevice device, const char* during) {
  const RTCError code = rtcGetDeviceError(device);
  if (code == RTC_ERROR_NONE) return;
  std::string message = t_embree_message.empty() ? errorName(code) : t_embree_message;
  t_embree_message.clear();
  throw std::runtime_error(std::string("Embree failed while ") + during + ": " + message);
}

// The one Embree device of the process: creating a device spins up Embree's
// thread pool, far too costly to repeat per mesh. Scenes hold their own
// reference, so releasing it at exit is safe whatever outlives it.
class SharedDevice {
public:
  SharedDevice() : device_(rtcNewDevice(nullptr)) {
    if (!device_) throw std::runtime_error(std::string("cannot create the Embree device: ") +
                                           errorName(rtcGetDeviceError(nullptr)));
    rtcSetDeviceErrorFunction(device_, recordEmbreeError, nullptr);
  }
  ~SharedDevice() { rtcReleaseDevice(device_); }
  SharedDevice(const SharedDevice&) = delete;
  SharedDevice& operator=(const SharedDevice&) = delete;
  RTCDevice get() const { return device_; }

private:
  RTCDevice device_;
};

RTCDevice sharedDevice() {
  static SharedDevice device;  // C++11 guarantees a thread-safe, retried-on-throw initialisation
  return device.get();
}

// What the filter callback records for one candidate on the all-hits path.
struct RawHit {
  unsigned face;
  float t, u, v;
};

// Embree passes our callback the RTCIntersectContext pointer it was given;
// keeping it the first member of a standard-layout struct lets the callback
// reach the query's own data from it.
struct QueryContext {
  RTCIntersectContext rtc;
  const std::uint8_t* mask = nullptr;  // null: every face can be hit
  std::vector<RawHit>* all = nullptr;  // null: closest hit only
};

void filterCandidates(const RTCFilterFunctionNArguments* args) {
  const auto* query = reinterpret_cast<const QueryContext*>(args->context);
  const unsigned n = args->N;
  for (unsigned i = 0; i < n; ++i) {
    if (args->valid[i] == 0) continue;
    const unsigned face = RTCHitN_primID(args->hit, n, i);
    if (query->mask && query->mask[face] == 0) {
      args->valid[i] = 0;
      continue;
    }
    if (query->all) {
      query->all->push_back({face, RTCRayN_tfar(args->ray, n, i), RTCHitN_u(args->hit, n, i),
                             RTCHitN_v(args->hit, n, i)});
      // Rejecting every candidate is what makes Embree keep traversing.
      args->valid[i] = 0;
    }
  }
}

void checkMaxDistance(double max_distance) {
  if (!(max_distance >= 0.0))
    throw std::invalid_argument("closest point: max_distance must be >= 0, got " + std::to_string(max_distance));
}

const std::uint8_t* checkedMask(const FaceMask& mask, std::size_t face_count) {
  if (mask.empty()) return nullptr;
  if (mask.size() != face_count)
    throw std::invalid_argument("face mask has " + std::to_string(mask.size()) + " entries, expected one per face (" +
                                std::to_string(face_count) + ")");
  return mask.data();
}

// Unit direction, or false when the direction cannot define a ray.
bool unitDirection(const Eigen::Vector3d& direction, Eigen::Vector3d& unit) {
  const double length = direction.norm();
  if (!(length > 0.0) || !std::isfinite(length)) return false;
  unit = direction / length;
  return true;
}

}  // namespace

struct RayCaster::Impl {
  // Per face, from the double-precision vertices: the unit normal and the
  // plane offset n . (a - offset). One cache line per hit instead of a face
  // and then its vertices (two dependent misses on random rays), and all a
  // hit needs to refine its distance. The bounding sphere in the same line
  // lets a closest-point query reject most candidate faces without
  // fetching their vertices.
  struct alignas(64) FacePlane {  // aligned: never straddles two cache lines
    Eigen::Vector3d normal;        // zero for a degenerate face
    double offset;
    Eigen::Vector3d centre;        // of the corners
    double radius;                 // the farthest corner from the centre
  };
  std::vector<FacePlane> planes;
  // Embree stores single-precision vertices; shifting them to the bounding
  // box centre keeps float rounding proportional to the mesh size rather
  // than to its distance from the world origin (georeferenced scans).
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  Eigen::AlignedBox3d local_bounds;  // bounds after the shift
  double extent = 0.0;               // bounding-box diagonal
  // Closest-point queries measure candidates in double precision, after the
  // same shift, so they need the vertices Embree only holds as floats.
  std::vector<Eigen::Vector3d> local_positions;
  std::vector<Triangle> faces;
  RTCScene scene = nullptr;

  explicit Impl(const TriangleMesh& mesh) {
    RTCDevice device = sharedDevice();
    const auto& positions = mesh.vertices.positions;
    if (!mesh.faces.empty()) {
      // Only the vertices of faces matter; isolated ones must not widen the box.
      Eigen::AlignedBox3d bounds;
      for (const Triangle& f : mesh.faces)
        for (int k = 0; k < 3; ++k) bounds.extend(positions[static_cast<std::size_t>(f[k])]);
      offset = bounds.center();
      local_bounds = Eigen::AlignedBox3d(bounds.min() - offset, bounds.max() - offset);
      extent = bounds.diagonal().norm();
    }
    faces = mesh.faces;
    local_positions.reserve(positions.size());
    for (const Eigen::Vector3d& p : positions) local_positions.push_back(p - offset);
    planes.reserve(mesh.faces.size());
    for (const Triangle& f : mesh.faces) {
      const Eigen::Vector3d& a = local_positions[static_cast<std::size_t>(f[0])];
      const Eigen::Vector3d& b = local_positions[static_cast<std::size_t>(f[1])];
      const Eigen::Vector3d& c = local_positions[static_cast<std::size_t>(f[2])];
      const Eigen::Vector3d normal = (b - a).cross(c - a);
      const double length = normal.norm();
      const Eigen::Vector3d unit = length > 0.0 ? Eigen::Vector3d(normal / length) : Eigen::Vector3d::Zero();
      const Eigen::Vector3d centre = (a + b + c) / 3.0;
      const double radius = std::max({(a - centre).norm(), (b - centre).norm(), (c - centre).norm()});
      planes.push_back({unit, unit.dot(a), centre, radius});
    }

    scene = rtcNewScene(device);
    throwOnEmbreeError(device, "creating a scene");
    try {
      // Robust: watertight edges, so lines through shared edges and
      // vertices are not lost. Context filter: masks and all-hits.
      rtcSetSceneFlags(scene,
                       static_cast<RTCSceneFlags>(RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION));
      if (!mesh.faces.empty()) attachTriangles(device, mesh);
      rtcCommitScene(scene);
      throwOnEmbreeError(device, "building the acceleration structure");
    } catch (...) {
      rtcReleaseScene(scene);  // no destructor runs for a constructor that throws
      throw;
    }
  }

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  void attachTriangles(RTCDevice device, const TriangleMesh& mesh) {
    const auto& positions = mesh.vertices.positions;
    const auto& faces = mesh.faces;
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    throwOnEmbreeError(device, "creating the triangle geometry");
    // Released right after attaching (the scene keeps it), also on failure.
    struct Release {
      RTCGeometry g;
      ~Release() { rtcReleaseGeometry(g); }
    } release{geometry};

    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), positions.size()));
    auto* indices = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), faces.size()));
    throwOnEmbreeError(device, "allocating the mesh buffers");
    for (std::size_t i = 0; i < positions.size(); ++i) {
      const Eigen::Vector3f p = (positions[i] - offset).cast<float>();
      vertices[3 * i] = p.x();
      vertices[3 * i + 1] = p.y();
      vertices[3 * i + 2] = p.z();
    }
    for (std::size_t i = 0; i < faces.size(); ++i)
      for (int k = 0; k < 3; ++k) indices[3 * i + static_cast<std::size_t>(k)] = static_cast<unsigned>(faces[i][k]);

    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    throwOnEmbreeError(device, "attaching the triangle geometry");
  }

  // Turns Embree's single-precision answer into a RayHit. The face is
  // Embree's; the distance is recomputed as the intersection of the line
  // with the face plane in double precision, which removes float rounding
  // from distances and points. Near-parallel (grazing) hits make that
  // plane intersection ill-conditioned, so Embree's distance stays when the
  // two disagree by more than float rounding can explain.
  RayHit makeHit(unsigned face, double t, float u, float v, const Eigen::Vector3d& origin,
                 const Eigen::Vector3d& local_origin, const Eigen::Vector3d& dir) const {
    RayHit hit;
    hit.hit = true;
    hit.face = static_cast<int>(face);
    hit.u = u;
    hit.v = v;
    const FacePlane& plane = planes[face];
    hit.face_normal = plane.normal;
    double distance = t;
    const double cosine = plane.normal.dot(dir);
    if (cosine != 0.0) {
      const double refined = (plane.offset - plane.normal.dot(local_origin)) / cosine;
      if (std::abs(refined - distance) <= 1e-5 * (std::abs(distance) + extent)) distance = refined;
    }
    hit.distance = distance;
    hit.point = origin + distance * dir;
    return hit;
  }

  static void setRay(RTCRay& ray, const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float tnear, float tfar) {
    ray.org_x = origin.x();
    ray.org_y = origin.y();
    ray.org_z = origin.z();
    ray.dir_x = dir.x();
    ray.dir_y = dir.y();
    ray.dir_z = dir.z();
    ray.tnear = tnear;
    ray.tfar = tfar;
    ray.time = 0.0f;
    ray.mask = ~0u;
    ray.id = 0;
    ray.flags = 0;
  }

  // A closest-hit query between Embree's answer and the finished RayHit.
  struct Pending {
    RTCRayHit query;
    Eigen::Vector3d local_origin, dir;
    double t_min;
  };

  static void initContext(QueryContext& context, const std::uint8_t* mask) {
    rtcInitIntersectContext(&context.rtc);
    if (mask) {
      context.mask = mask;
      context.rtc.filter = filterCandidates;
    }
  }

  // Returns whether Embree found a hit, leaving it in `pending`.
  bool trace(const Ray& ray, QueryContext& context, Pending& pending) const {
    if (planes.empty() || !unitDirection(ray.direction, pending.dir) || !ray.origin.allFinite()) return false;
    pending.t_min = std::max(ray.t_min, 0.0);  // Embree only takes ranges ahead of the origin
    if (!(pending.t_min <= ray.t_max)) return false;
    pending.local_origin = ray.origin - offset;
    setRay(pending.query.ray, pending.local_origin.cast<float>(), pending.dir.cast<float>(),
           static_cast<float>(pending.t_min), static_cast<float>(ray.t_max));
    pending.query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    pending.query.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context.rtc, &pending.query);
    return pending.query.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  }

  RayHit finish(const Ray& ray, const Pending& pending) const {
    const RTCHit& h = pending.query.hit;
    RayHit hit = makeHit(h.primID, pending.query.ray.tfar, h.u, h.v, ray.origin, pending.local_origin, pending.dir);
    // Refinement may move a hit found right at a window edge a rounding
    // error outside it; the documented window wins.
    if (hit.distance < pending.t_min || hit.distance > ray.t_max) {
      hit.distance = std::clamp(hit.distance, pending.t_min, ray.t_max);
      hit.point = ray.origin + hit.distance * pending.dir;
    }
    return hit;
  }

  RayHit closest(const Ray& ray, const std::uint8_t* mask) const {
    QueryContext context;
    initContext(context, mask);
    Pending pending;
    return trace(ray, context, pending) ? finish(ray, pending) : RayHit{};
  }

  // Many rays: all traced first, then all finished. The face data a hit
  // needs is then fetched while Embree works on the next rays (prefetch)
  // instead of stalling each ray on a cache miss at the end.
  void closestBatch(const Ray* rays, std::size_t count, const std::uint8_t* mask, RayHit* out) const {
    constexpr std::size_t kChunk = 32;
    QueryContext context;
    initContext(context, mask);
    Pending pending[kChunk];
    bool found[kChunk];
    for (std::size_t first = 0; first < count; first += kChunk) {
      const std::size_t n = std::min(kChunk, count - first);
      for (std::size_t i = 0; i < n; ++i) {
        found[i] = trace(rays[first + i], context, pending[i]);
        if (found[i]) __builtin_prefetch(&planes[pending[i].query.hit.primID]);
      }
      for (std::size_t i = 0; i < n; ++i) out[first + i] = found[i] ? finish(rays[first + i], pending[i]) : RayHit{};
    }
  }

  std::vector<RayHit> allOnLine(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                const std::uint8_t* mask) const {
    Eigen::Vector3d dir;
    if (planes.empty() || !unitDirection(direction, dir) || !origin.allFinite()) return {};

    // Embree rejects segments that start behind the origin, so the line is
    // cast as one ray starting just before the mesh bounding box: no face is
    // lost or doubled at the origin, as two opposite rays from it would risk.
    const Eigen::Vector3d local_origin = origin - offset;
    double s_lo = std::numeric_limits<double>::infinity();
    double s_hi = -s_lo;
    for (int corner = 0; corner < 8; ++corner) {
      const double s = dir.dot(local_bounds.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)) - local_origin);
      s_lo = std::min(s_lo, s);
      s_hi = std::max(s_hi, s);
    }
    const double margin = 1e-3 * extent + 1e-6;
    const double start = s_lo - margin;
    const Eigen::Vector3d local_start = local_origin + start * dir;

    std::vector<RawHit> raw;
    QueryContext context;
    rtcInitIntersectContext(&context.rtc);
    context.rtc.filter = filterCandidates;
    context.mask = mask;
    context.all = &raw;
    RTCRayHit query;
    setRay(query.ray, local_start.cast<float>(), dir.cast<float>(), 0.0f, static_cast<float>(s_hi - start + margin));
    query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    query.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context.rtc, &query);

    // A face can be offered more than once (Embree may test a primitive in
    // several leaves); each face counts once.
    std::sort(raw.begin(), raw.end(), [](const RawHit& a, const RawHit& b) { return a.face < b.face; });
    raw.erase(std::unique(raw.begin(), raw.end(), [](const RawHit& a, const RawHit& b) { return a.face == b.face; }),
              raw.end());

    std::vector<RayHit> hits;
    hits.reserve(raw.size());
    for (const RawHit& r : raw)
      hits.push_back(makeHit(r.face, start + r.t, r.u, r.v, origin, local_origin, dir));
    std::sort(hits.begin(), hits.end(), [](const RayHit& a, const RayHit& b) {
      return a.distance < b.distance || (a.distance == b.distance && a.face < b.face);
    });
    return hits;
  }

  // One closest-point query, as the Embree callback sees it.
  struct PointSearch {
    const Impl* impl;
    const std::uint8_t* mask;
    Eigen::Vector3d local_query;
    double max_distance;
    // Embree prunes with float boxes around float vertices, from a float
    // query point: each off by up to 2^-24 of its magnitude. A radius this
    // much above the double distance never prunes a face that could still
    // win, ties included.
    double slack;
    int face = -1;
    TrianglePoint best;
  };

  static bool visitCandidate(RTCPointQueryFunctionArguments* args) {
    auto& search = *static_cast<PointSearch*>(args->userPtr);
    const auto face = static_cast<int>(args->primID);
    if (search.mask && search.mask[face] == 0) return false;
    const Impl& impl = *search.impl;
    if (search.face >= 0) {
      // The distance to the plane and to the bounding sphere both bound the
      // distance to the face from below; with the slack, rounding in these
      // bounds cannot reject a face that the exact test would keep.
      const FacePlane& plane = impl.planes[static_cast<std::size_t>(face)];
      const double lower = std::max(std::abs(plane.normal.dot(search.local_query) - plane.offset),
                                    (search.local_query - plane.centre).norm() - plane.radius);
      if (lower > search.best.distance + search.slack) return false;
    }
    const Triangle& f = impl.faces[static_cast<std::size_t>(face)];
    const TrianglePoint candidate =
        closestPointOnTriangle(search.local_query, impl.local_positions[static_cast<std::size_t>(f[0])],
                               impl.local_positions[static_cast<std::size_t>(f[1])],
                               impl.local_positions[static_cast<std::size_t>(f[2])]);
    if (candidate.distance > search.max_distance) return false;
    // Embree's visiting order depends on the tree, not on face indices; the
    // explicit tie-break makes the answer a function of the mesh alone.
    if (search.face >= 0 && (candidate.distance > search.best.distance ||
                             (candidate.distance == search.best.distance && face > search.face)))
      return false;
    search.face = face;
    search.best = candidate;
    const auto radius = static_cast<float>(candidate.distance + search.slack);
    if (!(radius < args->query->radius)) return false;
    args->query->radius = radius;
    return true;  // tells Embree the query domain shrank
  }

  // Query indices in Morton (Z-curve) order of their positions in the mesh
  // box, queries outside clamped to it. A query mostly visits faces whose
  // data a cache miss fetches; in this order its neighbours visit the same
  // faces while they are still cached. Each answer depends on its query
  // alone, so the order changes the speed, never the results.
  std::vector<std::size_t> spatialOrder(const std::vector<Eigen::Vector3d>& queries) const {
    constexpr int kBits = 21;  // per axis: three fit in 64 bits
    const double top = double((1u << kBits) - 1);
    const Eigen::Vector3d scale = (top / local_bounds.sizes().array().max(1e-300)).matrix();
    std::vector<std::pair<std::uint64_t, std::size_t>> keys(queries.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, queries.size(), 4096),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          const Eigen::Vector3d cell =
                              (queries[i] - offset - local_bounds.min()).cwiseProduct(scale);
                          std::int64_t c[3];
                          for (int axis = 0; axis < 3; ++axis)  // NaN fails the comparison and lands in cell 0
                            c[axis] = static_cast<std::int64_t>(cell[axis] > 0.0 ? std::min(cell[axis], top) : 0.0);
                          keys[i] = {mortonCode(c[0], c[1], c[2]), i};
                        }
                      });
    tbb::parallel_sort(keys.begin(), keys.end());  // keys are unique: one order whatever the threads
    std::vector<std::size_t> order(keys.size());
    for (std::size_t k = 0; k < keys.size(); ++k) order[k] = keys[k].second;
    return order;
  }

  ClosestPoint closestPoint(const Eigen::Vector3d& query, double max_distance, const std::uint8_t* mask) const {
    if (planes.empty() || !query.allFinite()) return {};
    const Eigen::Vector3d local_query = query - offset;
    PointSearch search{this, mask, local_query, max_distance, 1e-6 * (extent + local_query.norm()), -1, {}};
    RTCPointQuery rtc_query;
    rtc_query.x = static_cast<float>(search.local_query.x());
    rtc_query.y = static_cast<float>(search.local_query.y());
    rtc_query.z = static_cast<float>(search.local_query.z());
    rtc_query.time = 0.0f;
    rtc_query.radius = static_cast<float>(max_distance + search.slack);  // infinity stays infinity
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(scene, &rtc_query, &context, visitCandidate, &search);
    if (search.face < 0) return {};
    ClosestPoint result;
    result.found = true;
    result.distance = search.best.distance;
    result.face = search.face;
    result.u = search.best.u;
    result.v = search.best.v;
    result.point = search.best.point + offset;
    result.face_normal = planes[static_cast<std::size_t>(search.face)].normal;
    return result;
  }
};

RayCaster::RayCaster(const TriangleMesh& mesh) {
  mesh.validate();
  impl_ = std::make_unique<Impl>(mesh);
}
RayCaster::~RayCaster() = default;
RayCaster::RayCaster(RayCaster&&) noexcept = default;
RayCaster& RayCaster::operator=(RayCaster&&) noexcept = default;

std::size_t RayCaster::faceCount() const { return impl_->planes.size(); }

RayHit RayCaster::closestHit(const Ray& ray, const FaceMask& mask) const {
  return impl_->closest(ray, checkedMask(mask, faceCount()));
}

std::vector<RayHit> RayCaster::allHitsOnLine(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                             const FaceMask& mask) const {
  return impl_->allOnLine(origin, direction, checkedMask(mask, faceCount()));
}

std::vector<RayHit> RayCaster::closestHits(const std::vector<Ray>& rays, const FaceMask& mask) const {
  const std::uint8_t* checked = checkedMask(mask, faceCount());
  std::vector<RayHit> hits(rays.size());
  // Rays are independent and cheap, so chunks amortise the scheduling.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      impl_->closestBatch(rays.data() + range.begin(), range.size(), checked,
                                          hits.data() + range.begin());
                    });
  return hits;
}

std::vector<std::vector<RayHit>> RayCaster::allHitsOnLines(const std::vector<Eigen::Vector3d>& origins,
                                                           const std::vector<Eigen::Vector3d>& directions,
                                                           const FaceMask& mask) const {
  if (origins.size() != directions.size())
    throw std::invalid_argument("allHitsOnLines: " + std::to_string(origins.size()) + " origins but " +
                                std::to_string(directions.size()) + " directions");
  const std::uint8_t* checked = checkedMask(mask, faceCount());
  std::vector<std::vector<RayHit>> hits(origins.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, origins.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i)
                        hits[i] = impl_->allOnLine(origins[i], directions[i], checked);
                    });
  return hits;
}

ClosestPoint RayCaster::closestPoint(const Eigen::Vector3d& query, double max_distance, const FaceMask& mask) const {
  checkMaxDistance(max_distance);
  return impl_->closestPoint(query, max_distance, checkedMask(mask, faceCount()));
}

std::vector<ClosestPoint> RayCaster::closestPoints(const std::vector<Eigen::Vector3d>& queries, double max_distance,
                                                   const FaceMask& mask) const {
  checkMaxDistance(max_distance);
  const std::uint8_t* checked = checkedMask(mask, faceCount());
  std::vector<ClosestPoint> points(queries.size());
  if (impl_->planes.empty()) return points;
  const std::vector<std::size_t> order = impl_->spatialOrder(queries);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, queries.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t k = range.begin(); k != range.end(); ++k) {
                        const std::size_t i = order[k];
                        points[i] = impl_->closestPoint(queries[i], max_distance, checked);
                      }
                    });
  return points;
}

}  // namespace icrkit
