#include <icrkit/icr/grasp_wrench_space.hpp>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

namespace icrkit::icr {
namespace {

// qhull reports through a FILE*; an in-memory stream keeps it off the
// terminal and lets the first line become the "not force closure" reason.
class MessageStream {
public:
  MessageStream() : file_(open_memstream(&buffer_, &size_)) {}
  ~MessageStream() {
    if (file_) std::fclose(file_);
    std::free(buffer_);
  }
  MessageStream(const MessageStream&) = delete;
  MessageStream& operator=(const MessageStream&) = delete;
  FILE* file() const { return file_; }
  std::string firstLine() {
    if (!file_) return {};
    std::fflush(file_);
    std::string text(buffer_ ? buffer_ : "", size_);
    const std::size_t start = text.find_first_not_of(" \n\r\t");
    if (start == std::string::npos) return {};
    const std::size_t end = text.find('\n', start);
    return text.substr(start, end == std::string::npos ? std::string::npos : end - start);
  }

private:
  char* buffer_ = nullptr;
  std::size_t size_ = 0;
  FILE* file_;
};

// Owns one reentrant qhull instance, so concurrent hulls never share state.
class QhullRun {
public:
  explicit QhullRun(FILE* errors) { qh_zero(&qh_, errors); }
  ~QhullRun() {
    qh_freeqhull(&qh_, !qh_ALL);
    int remaining_long = 0, total_long = 0;
    qh_memfreeshort(&qh_, &remaining_long, &total_long);
  }
  QhullRun(const QhullRun&) = delete;
  QhullRun& operator=(const QhullRun&) = delete;
  qhT* get() { return &qh_; }

private:
  qhT qh_;
};

}  // namespace

static GraspWrenchSpace buildHull(const WrenchSet& wrenches, const std::string& options, double threshold, bool& qhull_failed) {
  GraspWrenchSpace gws;
  gws.normals.resize(6, 0);
  const int count = static_cast<int>(wrenches.cols());
  if (count < 7) {
    gws.reason = "a 6-D hull needs at least 7 wrenches, the grasp has " + std::to_string(count);
    return gws;
  }
  if (!wrenches.allFinite()) {
    gws.reason = "a wrench has a non-finite component";
    return gws;
  }
  std::vector<coordT> points(wrenches.data(), wrenches.data() + wrenches.size());
  std::string command = "qhull " + options;
  gws.qhull_options = options;

  MessageStream messages;
  QhullRun run(messages.file());
  qhT* qh = run.get();
  const int exit_code = qh_new_qhull(qh, 6, count, points.data(), False, command.data(), nullptr, messages.file());
  if (exit_code != 0) {
    qhull_failed = true;
    std::string why = messages.firstLine();
    gws.reason = "no full-dimensional hull (qhull: " + (why.empty() ? "error " + std::to_string(exit_code) : why) + ")";
    return gws;
  }

  facetT* facet;
  vertexT* vertex;
  vertexT** vertexp;
  std::size_t facet_count = 0;
  FORALLfacets ++facet_count;
  gws.normals.resize(6, static_cast<Eigen::Index>(facet_count));
  gws.offsets.reserve(facet_count);
  gws.facet_vertices.reserve(facet_count);
  double epsilon = std::numeric_limits<double>::infinity();
  Eigen::Index f = 0;
  FORALLfacets {
    for (int k = 0; k < 6; ++k) gws.normals(k, f) = facet->normal[k];
    gws.offsets.push_back(facet->offset);
    epsilon = std::min(epsilon, -facet->offset);
    std::vector<int> ids;
    FOREACHvertex_(facet->vertices) ids.push_back(qh_pointid(qh, vertex->point));
    std::sort(ids.begin(), ids.end());
    gws.facet_vertices.push_back(std::move(ids));
    ++f;
  }
  FORALLvertices gws.hull_vertices.push_back(qh_pointid(qh, vertex->point));
  std::sort(gws.hull_vertices.begin(), gws.hull_vertices.end());

  gws.epsilon = epsilon;
  gws.force_closure = epsilon > threshold;
  if (!gws.force_closure)
    gws.reason = "the origin is not strictly inside the grasp wrench space (epsilon = " + std::to_string(epsilon) + ")";
  return gws;
}

bool hullContains(const GraspWrenchSpace& gws, const WrenchSet& wrenches, double relative_tolerance) {
  if (gws.facetCount() == 0 || wrenches.cols() == 0) return true;
  const double scale = wrenches.colwise().norm().maxCoeff();
  const double tolerance = relative_tolerance * std::max(scale, 1e-300);
  for (Eigen::Index f = 0; f < gws.normals.cols(); ++f) {
    const double limit = tolerance - gws.offsets[static_cast<std::size_t>(f)];
    if ((gws.normals.col(f).transpose() * wrenches).maxCoeff() > limit) return false;
  }
  return true;
}

GraspWrenchSpace computeGraspWrenchSpace(const WrenchSet& wrenches, const HullParameters& params) {
  bool qhull_failed = false;
  GraspWrenchSpace gws = buildHull(wrenches, params.qhull_options, params.force_closure_threshold, qhull_failed);
  const bool retry_possible = !params.fallback_options.empty() && params.fallback_options != params.qhull_options;
  // Without merging, qhull can keep a facet that a nearly coplanar wrench
  // lies beyond; one pass over all facets and wrenches (cheap next to the
  // hull) finds it.
  if (retry_possible && !qhull_failed && !hullContains(gws, wrenches, params.convexity_tolerance))
    qhull_failed = true;
  if (qhull_failed && retry_possible) {
    qhull_failed = false;
    gws = buildHull(wrenches, params.fallback_options, params.force_closure_threshold, qhull_failed);
  }
  return gws;
}

}  // namespace icrkit::icr
