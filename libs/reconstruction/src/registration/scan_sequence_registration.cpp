#include <icrkit/reconstruction/registration/scan_sequence_registration.hpp>

#include <icrkit/core/disjoint_sets.hpp>
#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/ndt/normal_estimation.hpp>

#include <icrkit/reconstruction/registration/pose_graph_variance.hpp>

#include "cube_key.hpp"
#include "view_pairs.hpp"
#include "model_alignment_levels.hpp"
#include "registration_observability.hpp"
#include "unsettled_pairs.hpp"
#include "view_overlap.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>

#include <tbb/parallel_for.h>

namespace icrkit::reconstruction {

namespace {

using Clock = std::chrono::steady_clock;

double rotationAngle(const Eigen::Isometry3d& t) { return Eigen::AngleAxisd(t.rotation()).angle(); }

bool finitePose(const Eigen::Isometry3d& t) { return t.matrix().allFinite(); }

// The mean of `points` (zero for none).
Eigen::Vector3d centroidOf(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) sum += p;
  return points.empty() ? sum : Eigen::Vector3d(sum / double(points.size()));
}

// A pair's record before it is registered (a fresh attempt inherits no
// scores from an earlier one).
PairRegistrationRecord unregisteredPair(std::size_t from, std::size_t to, double overlap, int round) {
  PairRegistrationRecord record;
  record.from = from;
  record.to = to;
  record.overlap = overlap;
  record.round = round;
  return record;
}

PointCloud positionsOnly(const std::vector<Eigen::Vector3d>& points) {
  PointCloud cloud;
  cloud.positions = points;
  return cloud;
}

// Unit normals of a scan's points (scan frame), or none for too few points.
// Neither the point-to-plane residual nor the observability depends on a
// normal's sign: facing them to the sensor (the frame's origin) costs
// nothing, orienting them over a neighbour graph a third of their time.
std::optional<std::vector<Eigen::Vector3d>> tangentNormals(const std::vector<Eigen::Vector3d>& points,
                                                           bool index_order) {
  PointCloud cloud = positionsOnly(points);
  ndt::NormalEstimationParameters facing;
  facing.viewpoint = Eigen::Vector3d::Zero();
  facing.index_order = index_order;
  try {
    ndt::estimateNormals(cloud, facing);
  } catch (const InputError&) {
    return std::nullopt;
  }
  return std::move(cloud.normals);
}

// Centroids of the model's points per cube. An ordered map: the target is
// built from the centroids in key order, so the model does not depend on
// hash-table layout.
class VoxelModel {
public:
  explicit VoxelModel(double size) : size_(size) {}

  void add(const std::vector<Eigen::Vector3d>& points, const Eigen::Isometry3d& pose) {
    for (const Eigen::Vector3d& local : points) {
      const Eigen::Vector3d p = pose * local;
      Cell& cell = cells_[cubeKey(p, size_)];
      cell.sum += p;
      ++cell.count;
    }
  }

  std::size_t size() const { return cells_.size(); }

  PointCloud centroids() const {
    PointCloud cloud;
    cloud.positions.reserve(cells_.size());
    for (const auto& [key, cell] : cells_) cloud.positions.push_back(cell.sum / double(cell.count));
    return cloud;
  }

private:
  struct Cell {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int count = 0;
  };
  double size_;
  std::map<std::int64_t, Cell> cells_;
};

// Where a scan, placed by `pose`, constrains a registration (surface
// stability of its points and normals, scan frame).
Observability scanObservability(const std::vector<Eigen::Vector3d>& points,
                                const std::vector<Eigen::Vector3d>& normals, const Eigen::Isometry3d& pose,
                                double ratio) {
  std::vector<Eigen::Vector3d> p(points.size()), n(normals.size());
  for (std::size_t i = 0; i < points.size(); ++i) p[i] = pose * points[i];
  for (std::size_t i = 0; i < normals.size(); ++i) n[i] = pose.linear() * normals[i];
  return surfaceObservability(p, n, std::max(ratio, 0.0));
}

// Keeps the registration's correction of `start` only where it is observed.
void remapDegenerate(ndt::NdtResult& r, const Eigen::Isometry3d& start, const Observability& o) {
  if (o.degenerate_directions > 0)
    r.pose = smallMotionExp(o.projector * smallMotionLog(r.pose * start.inverse())) * start;
}

// The largest eigenvalue of the Hessian's translation block: how strongly a
// registration constrains its best-determined translation.
double translationStiffness(const Matrix6d& hessian) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(0.5 * (hessian.topLeftCorner<3, 3>() +
                                                                    hessian.topLeftCorner<3, 3>().transpose()));
  return eigen.eigenvalues()(2);
}

// The information of a pair edge (right perturbation of `measurement`, the
// pose graph's convention) from the NDT Hessian (left perturbation in the
// target frame), scaled by `scale`.
Matrix6d hessianInformation(const Matrix6d& hessian, const Matrix6d& projector, const Eigen::Isometry3d& measurement,
                            double scale) {
  // Nothing is known along the unobserved directions: the projected
  // Hessian has no information there.
  const Matrix6d projected = projector.transpose() * hessian * projector;
  const Matrix6d h = 0.5 * (projected + projected.transpose());
  if (!(scale > 0) || !h.allFinite()) return Matrix6d::Identity();
  // The Hessian is semi-definite at best; a floor of 1 m / 1 rad keeps the
  // information definite without constraining anything.
  Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(h * scale);
  const Matrix6d left =
      eigen.eigenvectors() * (eigen.eigenvalues().cwiseMax(0.0).array() + 1.0).matrix().asDiagonal() *
      eigen.eigenvectors().transpose();
  const Matrix6d ad = adjoint(measurement);
  const Matrix6d right = ad.transpose() * left * ad;
  return 0.5 * (right + right.transpose());
}

// Per scan, built once and shared read-only by every pair it is part of:
// its NDT target, and for the fine stage its tangent planes (target side)
// and a sparser copy of its points (source side); and the cubes it lends
// the model alignment.
struct ScanParts {
  std::optional<ndt::NdtTarget> ndt_target;
  std::optional<IcpTarget> icp_target;
  std::vector<Eigen::Vector3d> icp_source, ndt_source, model_points;
};

// Cubes (metres) a view's points are reduced to when it is part of another
// view's model: a 1 cm NDT cell then gets ~16 points per view that sees it.
constexpr double kModelAlignmentVoxel = 0.0025;

// Incremental alignment: a view is aligned to the earlier ones when at
// least `min_pair_overlap` of its cubes of this size (coarse enough that a
// reported pose a centimetre off still finds them) is occupied by them.
constexpr double kCoverageCube = 0.02;

}  // namespace

void SequenceRegistrationParameters::validate() const {
  const SequenceRegistrationParameters& p = *this;
  auto positive = [](double v, const char* name) {
    if (!(v > 0) || !std::isfinite(v)) throw InputError(name, "", "expected a positive number");
  };
  positive(p.model_voxel_size, "model_voxel_size");
  positive(p.max_correction_translation, "max_correction_translation");
  positive(p.max_correction_rotation, "max_correction_rotation");
  positive(p.registration_sigma_translation, "registration_sigma_translation");
  positive(p.registration_sigma_rotation, "registration_sigma_rotation");
  if (!std::isfinite(p.min_normalized_score)) throw InputError("min_normalized_score", "", "expected a number");
  if (!(p.joint_min_linked_pair_ratio >= 0) || !std::isfinite(p.joint_min_linked_pair_ratio))
    throw InputError("joint_min_linked_pair_ratio", "", "expected a number >= 0");
  if ((p.prior_sigma_translation > 0) != (p.prior_sigma_rotation > 0))
    throw InputError("prior_sigma_translation / prior_sigma_rotation", "", "set both (> 0) or neither");
  if (p.ndt.resolutions.empty()) throw InputError("ndt.resolutions", "", "expected at least one resolution");
  if (!(p.reseat_min_shared_cubes >= 0 && p.reseat_min_shared_cubes <= 1))
    throw InputError("reseat_min_shared_cubes", "", "expected a share between 0 and 1");
  if (!(p.reseat_min_pair_cubes >= 0 && p.reseat_min_pair_cubes <= 1))
    throw InputError("reseat_min_pair_cubes", "", "expected a share between 0 and 1");
  if (p.reseat_min_shared_cubes > 0 || p.reseat_min_pair_cubes > 0 || p.reseat_search_step > 0)
    positive(p.reseat_overlap_cube, "reseat_overlap_cube");
  if (!(p.reseat_search_step >= 0) || !std::isfinite(p.reseat_search_step))
    throw InputError("reseat_search_step", "", "expected a step >= 0 (metres; 0: no search)");
  // 5 steps: 1330 starts a view, already far beyond the levels' reach.
  if (p.reseat_search_steps < 1 || p.reseat_search_steps > 5)
    throw InputError("reseat_search_steps", "", "expected 1 to 5 steps along each axis");
  if (p.reseat_passes < 1 || p.reseat_passes > 10) throw InputError("reseat_passes", "", "expected 1 to 10 passes");
  if (p.refinement_rounds < 0)
    throw InputError("refinement_rounds", "", "expected 0 (automatic) or a positive number of rounds");
  if (!(p.unsettled_pair_move > 0) || !std::isfinite(p.unsettled_pair_move))
    throw InputError("unsettled_pair_move", "", "expected a distance > 0 (metres)");
  if (p.max_unsettled_rounds < 0 || p.max_unsettled_rounds > 10)
    throw InputError("max_unsettled_rounds", "", "expected 0 to 10 more rounds");
  if (!(p.model_alignment_max_cell_to_spread >= 0) || !std::isfinite(p.model_alignment_max_cell_to_spread))
    throw InputError("model_alignment_max_cell_to_spread", "", "expected a ratio >= 0 (0: every level)");
}

struct SequenceRegistration::Impl {
  explicit Impl(const SequenceRegistrationParameters& p) : params(p), model(p.model_voxel_size) {}

  SequenceRegistrationParameters params;
  VoxelModel model;
  std::optional<ndt::NdtTarget> target;  // the model as of the last accepted scan
  std::vector<ScanRegistrationRecord> records;
  std::vector<std::optional<PosePrior>> priors;  // per scan, besides the reported pose
  std::vector<std::vector<Eigen::Vector3d>> reduced;  // every scan, kept_voxel_size centroids, its own frame
  std::vector<std::vector<Eigen::Vector3d>> normals;  // of `reduced` (unoriented), for the observability
  Eigen::Isometry3d correction = Eigen::Isometry3d::Identity();  // latest model_pose * initial_pose^-1
  double time_ms = 0.0;
  bool finished = false;
  // Set when add() failed after it began to change the state (out of
  // memory, a solver failure): the per-scan arrays may then disagree, so
  // every later call refuses instead of registering from a torn state.
  std::string broken;

  // Incremental registration (params.incremental): built by add() as the
  // scans arrive.
  std::vector<ScanParts> parts;
  std::vector<Eigen::Isometry3d> aligned;  // each view after its alignment to the earlier ones
  std::vector<std::vector<std::int64_t>> cubes;  // the 1 cm cubes each view occupies at `aligned`
  std::vector<PairRegistrationRecord> early_pairs;  // every view with its best earlier partners
  std::vector<Matrix6d> early_hessians, early_projectors;
  std::vector<std::size_t> level_kept;  // views the alignment kept, per level
  std::vector<std::int64_t> covered_cubes;  // kCoverageCube cubes the views so far occupy, sorted

  void prepare(std::size_t i, ScanParts& out);
  void registerPair(const std::vector<ScanParts>& all, const std::vector<Eigen::Isometry3d>& poses, int round,
                    bool both_placed, PairRegistrationRecord& pair, Matrix6d& hessian, Matrix6d& projector) const;
  void attemptPair(const std::vector<ScanParts>& all, const std::vector<Eigen::Isometry3d>& poses, int round,
                   bool coarse_start, PairRegistrationRecord& pair, Matrix6d& hessian, Matrix6d& projector) const;
  /// A first-round pair registered again with the coarse start (the
  /// pair's NDT before the ICP), its record and information replaced.
  void retryPairCoarse(const std::vector<ScanParts>& all, const std::vector<Eigen::Isometry3d>& poses,
                       PairRegistrationRecord& pair, Matrix6d& hessian, Matrix6d& projector) const;
  /// The first round's pairs of placed views that the ICP rejected for
  /// too little overlap and that would join views the accepted pairs
  /// leave apart, registered again with the coarse start
  /// (`pair_ndt_retry_rejected`).
  void retryBridgingPairs(const std::vector<ScanParts>& all, const std::vector<Eigen::Isometry3d>& poses,
                          const std::vector<std::uint8_t>& placed, std::vector<PairRegistrationRecord>& pairs,
                          std::vector<Matrix6d>& hessians, std::vector<Matrix6d>& projectors,
                          SequenceRegistrationResult& result) const;
  /// The next round's pairs when the last one left stale pairs
  /// (`max_unsettled_rounds`): the last round's `pairs`, those that would
  /// join views its accepted pairs leave apart (its rejected ones and
  /// those chosen anew at the graph's `poses`) registered from `poses` (of
  /// those, `registered`; `accepted_links` accepted as full links; the
  /// round is worth running only when some are).
  struct UnsettledRound {
    std::vector<PairRegistrationRecord> pairs;
    std::vector<Matrix6d> hessians, projectors;
    std::size_t registered = 0, accepted_links = 0;
  };
  UnsettledRound linkUnsettledGroups(const std::vector<ScanParts>& all, const std::vector<Eigen::Isometry3d>& poses,
                                     int round, const std::vector<PairRegistrationRecord>& pairs,
                                     const std::vector<Matrix6d>& hessians,
                                     const std::vector<Matrix6d>& projectors) const;
  void alignAndPair(std::size_t i);
  void commit(const PointCloud& points, ScanRegistrationRecord record, std::vector<Eigen::Vector3d> reduced_points,
              std::vector<Eigen::Vector3d> reduced_normals, const std::optional<PosePrior>& prior,
              const Eigen::Isometry3d& moved, Clock::time_point start);
  void firstRoundPairs(std::vector<PairRegistrationRecord>& pairs, std::vector<Matrix6d>& hessians,
                       std::vector<Matrix6d>& projectors) const;

  std::vector<Eigen::Vector3d> reduce(const PointCloud& cloud) const {
    // The NDT reduces its source to cube centroids itself; reducing once
    // here also bounds what is kept for the loop closure.
    if (params.kept_voxel_size <= 0) return cloud.positions;
    VoxelModel cubes(params.kept_voxel_size);
    cubes.add(cloud.positions, Eigen::Isometry3d::Identity());
    return cubes.centroids().positions;
  }

  // The NDT of the scan-to-model pass and of the pairs: with the ICP's
  // fine stage after it, only its cells of at least
  // `icp_coarsest_finish` (the ICP finishes from there).
  ndt::NdtParameters coarseNdt() const {
    ndt::NdtParameters ndt = params.ndt;
    if (!params.icp_refinement) return ndt;
    std::vector<double> kept;
    for (double r : ndt.resolutions)
      if (r >= params.icp_coarsest_finish) kept.push_back(r);
    if (kept.empty()) kept.push_back(ndt.resolutions.front());
    ndt.resolutions = kept;
    return ndt;
  }

  double first_spacing = 0.0;
  void adaptResolutions(const std::vector<Eigen::Vector3d>& points) {
    first_spacing = nearestNeighbourSpacing(points).median;
    // The ICP's pairing distances and kernel are a depth camera's at arm's
    // length (~1 mm spacing and noise); a sparser, noisier camera (a
    // 176 x 144 ToF sensor: 2-3 mm) gets them scaled with its spacing.
    if (params.icp_spacing_reference > 0 && first_spacing > params.icp_spacing_reference) {
      const double scale = first_spacing / params.icp_spacing_reference;
      for (double& d : params.icp.max_distances) d *= scale;
      params.icp.kernel_width *= scale;
      // Its views' cubes too: with a few points per 4 mm cube, two views
      // of the same surface occupy different ones (a real ToF camera's
      // view in place shared 0.10 of them).
      params.reseat_overlap_cube *= scale;
    }
    if (!(params.min_resolution_spacing_factor > 0) || !(first_spacing > 0)) return;
    std::vector<double> kept;
    for (double r : params.ndt.resolutions)
      if (r >= params.min_resolution_spacing_factor * first_spacing) kept.push_back(r);
    if (kept.empty()) kept.push_back(params.ndt.resolutions.front());
    params.ndt.resolutions = kept;
  }

  std::vector<Eigen::Vector3d> surfaceNormals(const std::vector<Eigen::Vector3d>& points) const {
    if (!(params.degeneracy_ratio > 0)) return {};
    // Too few points: nothing observed.
    return tangentNormals(points, params.normals_in_index_order).value_or(std::vector<Eigen::Vector3d>(points.size(), Eigen::Vector3d::Zero()));
  }

  // Why a registration result is not used, or empty when it is. The move
  // from `reference` is measured where it matters, at the source points'
  // centroid (a scan frame's origin is the sensor, ~0.7 m away, where a
  // small rotation alone is a large translation).
  std::string judge(const ndt::NdtResult& r, const Eigen::Isometry3d& reference,
                    const std::vector<Eigen::Vector3d>& source, const char* what) const {
    const Eigen::Vector3d centroid = centroidOf(source);
    const double shift = (r.pose * centroid - reference * centroid).norm();
    const double angle = rotationAngle(r.pose * reference.inverse());
    if (shift > params.max_correction_translation)
      return "moved the points " + std::to_string(shift * 1e3) + " mm from " + what + " (limit " +
             std::to_string(params.max_correction_translation * 1e3) + " mm)";
    if (angle > params.max_correction_rotation)
      return "rotated " + std::to_string(angle * 180 / M_PI) + " deg from " + what + " (limit " +
             std::to_string(params.max_correction_rotation * 180 / M_PI) + " deg)";
    if (r.normalized_score < params.min_normalized_score)
      return "normalised NDT score " + std::to_string(r.normalized_score) + " below " +
             std::to_string(params.min_normalized_score);
    return {};
  }
};

SequenceRegistration::SequenceRegistration(const SequenceRegistrationParameters& params) {
  params.validate();
  impl_ = std::make_unique<Impl>(params);
}

SequenceRegistration::~SequenceRegistration() = default;

std::size_t SequenceRegistration::size() const { return impl_->records.size(); }

std::size_t SequenceRegistration::pointBytes() const {
  const Impl& s = *impl_;
  std::size_t points = 0;
  for (const auto& v : s.reduced) points += v.size();
  for (const auto& v : s.normals) points += v.size();
  for (const ScanParts& p : s.parts) {
    points += p.icp_source.size() + p.ndt_source.size() + p.model_points.size();
    if (p.ndt_target) points += p.ndt_target->size();
    if (p.icp_target) points += 2 * p.icp_target->points().size();
  }
  return points * sizeof(Eigen::Vector3d);
}

const ScanRegistrationRecord& SequenceRegistration::add(const PointCloud& points, const Eigen::Isometry3d& initial_pose,
                                                        const std::optional<PosePrior>& prior) {
  Impl& s = *impl_;
  if (s.finished) throw std::logic_error("SequenceRegistration::add after finish()");
  if (!s.broken.empty()) throw std::logic_error("SequenceRegistration::add after a failed add(): " + s.broken);
  const auto start = Clock::now();
  const std::size_t index = s.records.size();
  const std::string where = "scan " + std::to_string(index);
  if (points.positions.empty()) throw InputError(where, "", "no points to register (everything was filtered out?)");
  for (std::size_t i = 0; i < points.positions.size(); ++i)
    if (!points.positions[i].allFinite())
      throw InputError(where, "point " + std::to_string(i), "non-finite coordinate");
  if (!finitePose(initial_pose)) throw InputError(where, "", "non-finite initial pose");
  if (prior && (!finitePose(prior->pose) || !(prior->sigma_translation > 0) || !(prior->sigma_rotation > 0) ||
                !std::isfinite(prior->sigma_translation) || !std::isfinite(prior->sigma_rotation)))
    throw InputError(where, "", "expected a finite prior pose with standard deviations > 0");

  ScanRegistrationRecord record;
  record.index = index;
  record.points = points.positions.size();
  record.initial_pose = initial_pose;
  record.start_pose = s.params.propagate_correction ? s.correction * initial_pose : initial_pose;
  record.model_pose = record.start_pose;
  // From here on the state changes (the first scan adapts the parameters):
  // a failure leaves the object refusing further calls.
  try {
    if (index == 0) s.adaptResolutions(points.positions);
    std::vector<Eigen::Vector3d> reduced = s.reduce(points);
    // Only the scan-to-model pass needs them now; finish() estimates the
    // others for all scans at once, in parallel.
    std::vector<Eigen::Vector3d> normals;
    if (s.params.scan_to_model) normals = s.surfaceNormals(reduced);

    if (index == 0 || !s.params.scan_to_model) {
      record.model_pose = initial_pose;
      record.start_pose = initial_pose;
      if (index > 0) record.rejection = "scan-to-model registration is off";
    } else if (!s.target) {
      record.rejection = "no model to register against (every earlier scan was rejected)";
    } else {
      record.model_points = s.target->size();
      const ndt::NdtParameters ndt = s.coarseNdt();
      try {
        ndt::NdtResult r = ndt::registerNdt(positionsOnly(reduced), *s.target, record.start_pose, ndt);
        const Observability o = scanObservability(reduced, normals, record.start_pose, s.params.degeneracy_ratio);
        if (s.params.degeneracy_ratio > 0) remapDegenerate(r, record.start_pose, o);
        record.degenerate_directions = o.degenerate_directions;
        record.weakest_direction_ratio = o.weakest_ratio;
        record.normalized_score = r.normalized_score;
        record.iterations = r.iterations;
        record.converged = r.converged;
        record.rejection = s.judge(r, initial_pose, reduced, "the reported pose");
        if (record.rejection.empty()) {
          record.registered = true;
          record.model_pose = r.pose;
        }
      } catch (const InputError& e) {
        record.rejection = std::string("NDT: ") + e.what();
      }
    }
    const Eigen::Isometry3d moved = record.model_pose * initial_pose.inverse();
    record.correction_translation_m = moved.translation().norm();
    record.correction_rotation_rad = rotationAngle(moved);
    s.commit(points, std::move(record), std::move(reduced), std::move(normals), prior, moved, start);
  } catch (const std::exception& e) {
    s.broken = e.what();
    throw;
  }
  return s.records.back();
}

void SequenceRegistration::Impl::commit(const PointCloud& points, ScanRegistrationRecord record,
                                        std::vector<Eigen::Vector3d> reduced_points,
                                        std::vector<Eigen::Vector3d> reduced_normals,
                                        const std::optional<PosePrior>& prior, const Eigen::Isometry3d& moved,
                                        Clock::time_point start) {
  Impl& s = *this;
  const std::size_t index = record.index;
  if (s.params.scan_to_model && (index == 0 || record.registered)) {
    s.correction = moved;
    s.model.add(points.positions, record.model_pose);
    try {
      s.target.emplace(s.model.centroids(), s.coarseNdt());
    } catch (const InputError&) {
      // Too few points for any Gaussian yet: later scans add to the model.
      s.target.reset();
    }
  }
  s.reduced.push_back(std::move(reduced_points));
  s.normals.push_back(std::move(reduced_normals));
  record.time_ms = millisecondsSince(start);
  s.time_ms += record.time_ms;
  s.priors.push_back(prior);
  s.records.push_back(std::move(record));
  if (s.params.incremental) {
    const auto aligning = Clock::now();
    s.alignAndPair(index);
    const double ms = millisecondsSince(aligning);
    s.records.back().time_ms += ms;
    s.time_ms += ms;
  }
}

namespace {

// The 1 cm cubes a scan's points occupy at a pose, sorted (for overlaps).
std::vector<std::int64_t> occupiedCubes(const std::vector<Eigen::Vector3d>& points, const Eigen::Isometry3d& pose) {
  return occupiedCubeKeys(points, pose, 0.01);
}

double overlapFraction(const std::vector<std::int64_t>& a, const std::vector<std::int64_t>& b) {
  if (a.empty() || b.empty()) return 0.0;
  std::size_t shared = 0;
  for (auto i = a.begin(), j = b.begin(); i != a.end() && j != b.end();) {
    if (*i < *j) ++i;
    else if (*j < *i) ++j;
    else { ++shared; ++i; ++j; }
  }
  return double(shared) / double(std::min(a.size(), b.size()));
}

}  // namespace

namespace {

// The pairs to register at `poses`: the best-overlapping partners of every
// scan and, optionally, the last/first pair (loop closure).
std::map<std::pair<std::size_t, std::size_t>, double> choosePairs(
    const std::vector<std::vector<Eigen::Vector3d>>& reduced, const std::vector<Eigen::Isometry3d>& poses,
    const SequenceRegistrationParameters& params) {
  const std::size_t n = reduced.size();
  std::vector<std::vector<std::int64_t>> cubes(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) { cubes[i] = occupiedCubes(reduced[i], poses[i]); });
  std::map<std::pair<std::size_t, std::size_t>, double> chosen;
  const std::size_t limit = static_cast<std::size_t>(std::max(0, params.max_partners));
  for (std::size_t j = 0; j < n; ++j) {
    std::vector<std::pair<double, std::size_t>> partners;
    for (std::size_t i = 0; i < n; ++i) {
      if (i == j) continue;
      const double overlap = overlapFraction(cubes[i], cubes[j]);
      if (overlap >= params.min_pair_overlap) partners.emplace_back(-overlap, i);
    }
    std::sort(partners.begin(), partners.end());
    if (partners.size() > limit) partners.resize(limit);
    for (const auto& [negative_overlap, i] : partners) chosen[{std::min(i, j), std::max(i, j)}] = -negative_overlap;
  }
  if (params.loop_closure && n >= 3)
    chosen.emplace(std::make_pair(std::size_t{0}, n - 1), overlapFraction(cubes[0], cubes[n - 1]));
  // Consecutive scans overlap however poorly the robot placed them: from
  // poses a centimetre off, their cubes hardly meet.
  if (params.sequence_pairs)
    for (std::size_t i = 0; i + 1 < n; ++i) chosen.emplace(std::make_pair(i, i + 1), overlapFraction(cubes[i], cubes[i + 1]));
  return chosen;
}

// Robust per-axis sigma of a set of zero-mean components (MAD).
double robustSigma(std::vector<double> magnitudes) {
  if (magnitudes.empty()) return 0.0;
  const auto middle = magnitudes.begin() + static_cast<std::ptrdiff_t>(magnitudes.size() / 2);
  std::nth_element(magnitudes.begin(), middle, magnitudes.end());
  return 1.4826 * *middle;
}

}  // namespace

namespace {

// One level of the model alignment: an NDT with `resolution` cells and
// no further reduction of the source.
ndt::NdtParameters alignmentLevel(const SequenceRegistrationParameters& params, double resolution) {
  ndt::NdtParameters level = params.ndt;
  level.resolutions = {resolution};
  level.source_voxel_size = 0.0;
  return level;
}

// A coarse cell needs no 2.5 mm detail: the views' 5 mm cubes give it as
// many points per cell as the finer ones give a 1 cm cell.
bool coarseAlignmentLevel(const SequenceRegistrationParameters& params, double resolution) {
  return resolution >= 8.0 * params.pair_ndt_source_voxel_size;
}

// What a view is aligned against at one level: the points of the views
// `use` selects among the first poses.size(), each moved by its pose, in
// view order (their 5 mm cubes for a coarse level, the 2.5 mm ones else).
template <class Use>
PointCloud modelOfViews(const SequenceRegistrationParameters& params, double resolution,
                        const std::vector<ScanParts>& parts, const std::vector<Eigen::Isometry3d>& poses, Use use) {
  const bool coarse = coarseAlignmentLevel(params, resolution);
  PointCloud model;
  for (std::size_t j = 0; j < poses.size(); ++j)
    if (use(j))
      for (const Eigen::Vector3d& p : coarse ? parts[j].ndt_source : parts[j].model_points)
        model.positions.push_back(poses[j] * p);
  return model;
}

// A view's alignment at one level: where it ends, its normalised NDT
// score, and whether a turned start (the retry) got it there.
struct ViewAlignment {
  Eigen::Isometry3d pose;
  double score = 0.0;
  bool retried = false;
  bool from_also = false;  // the `also_from` start scored best
};

// One view against a model of other views at one level, from `from_pose`:
// its alignment when the result is kept (near the reported pose, scored
// well enough). `reported` is the robot's pose (the limits), `reduced` and
// `normals` the view's points and normals (its observability),
// `source_points` the points registered and `centroid` theirs. With
// `also_from`, the NDT runs from there too and the better score is kept:
// the second level judges a view the first placed only from a turned
// start (a wrong basin can score better on the coarse cells) against its
// unturned pose. Throws InputError when the NDT cannot run.
std::optional<ViewAlignment> alignView(const SequenceRegistrationParameters& params, const ndt::NdtTarget& target,
                                       double resolution, const Eigen::Isometry3d& reported,
                                       const std::vector<Eigen::Vector3d>& reduced,
                                       const std::vector<Eigen::Vector3d>& normals,
                                       const std::vector<Eigen::Vector3d>& source_points,
                                       const Eigen::Vector3d& centroid, const Eigen::Isometry3d& from_pose,
                                       const std::optional<Eigen::Isometry3d>& also_from = std::nullopt) {
  const ndt::NdtParameters level = alignmentLevel(params, resolution);
  const PointCloud source = positionsOnly(source_points);
  // The NDT from `from`; its result when it is kept.
  auto attempt = [&](const Eigen::Isometry3d& from) -> std::optional<ndt::NdtResult> {
    ndt::NdtResult r = ndt::registerNdt(source, target, from, level);
    if (params.degeneracy_ratio > 0)
      remapDegenerate(r, from, scanObservability(reduced, normals, from, params.degeneracy_ratio));
    const bool near = (r.pose * centroid - reported * centroid).norm() <= params.model_alignment_max_translation &&
                      rotationAngle(r.pose * reported.inverse()) <= params.model_alignment_max_rotation;
    if (near && r.normalized_score >= params.min_normalized_score && finitePose(r.pose)) return r;
    return std::nullopt;
  };
  std::optional<ndt::NdtResult> best = attempt(from_pose);
  bool retried = false;
  // A view the coarsest level could not place (from tens of millimetres
  // off it turned around a round object instead): again from the camera
  // turned a little about its two axes across the line of sight, which
  // moves the object sideways in the image; the best score of those kept
  // wins.
  if (!best && resolution == params.model_alignment_resolutions.front() && params.model_alignment_retry_angle > 0) {
    const double a = params.model_alignment_retry_angle;
    for (int u = -1; u <= 1; ++u)
      for (int v = -1; v <= 1; ++v) {
        if (u == 0 && v == 0) continue;
        const Eigen::Isometry3d turned = from_pose * Eigen::AngleAxisd(u * a, Eigen::Vector3d::UnitY()) *
                                         Eigen::AngleAxisd(v * a, Eigen::Vector3d::UnitZ());
        std::optional<ndt::NdtResult> r = attempt(turned);
        if (r && (!best || r->normalized_score > best->normalized_score)) {
          best = r;
          retried = true;
        }
      }
  }
  bool from_also = false;
  if (also_from) {
    std::optional<ndt::NdtResult> r = attempt(*also_from);
    if (r && (!best || r->normalized_score > best->normalized_score)) {
      best = r;
      retried = false;
      from_also = true;
    }
  }
  if (!best) return std::nullopt;
  return ViewAlignment{best->pose, best->normalized_score, retried, from_also};
}

// The median and largest move of the views' points from `start` to `poses`.
void recordAlignmentMoves(const std::vector<ScanParts>& parts, const std::vector<Eigen::Isometry3d>& start,
                          const std::vector<Eigen::Isometry3d>& poses, SequenceRegistrationResult& result) {
  std::vector<double> moves;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (parts[i].ndt_source.empty()) continue;
    const Eigen::Vector3d centroid = centroidOf(parts[i].ndt_source);
    moves.push_back((poses[i] * centroid - start[i] * centroid).norm());
  }
  if (!moves.empty()) {
    result.model_alignment_max_move_m = *std::max_element(moves.begin(), moves.end());
    std::nth_element(moves.begin(), moves.begin() + static_cast<std::ptrdiff_t>(moves.size() / 2), moves.end());
    result.model_alignment_median_move_m = moves[moves.size() / 2];
  }
}

// The model alignment (SequenceRegistrationParameters::
// model_alignment_resolutions): every view against the union of the others,
// all from the same poses, one level at a time.
// `reported` are the robot's poses (the limits), `reduced` and `normals`
// each view's points and normals (its observability).
void alignToOthers(const SequenceRegistrationParameters& params, const std::vector<Eigen::Isometry3d>& reported,
                   const std::vector<std::vector<Eigen::Vector3d>>& reduced,
                   const std::vector<std::vector<Eigen::Vector3d>>& normals, const std::vector<ScanParts>& parts,
                   std::vector<Eigen::Isometry3d>& poses, std::vector<std::uint8_t>& placed,
                   SequenceRegistrationResult& result) {
  const std::vector<Eigen::Isometry3d> start = poses;
  const std::size_t n = poses.size();
  std::vector<Eigen::Vector3d> centroids(n);
  for (std::size_t i = 0; i < n; ++i) centroids[i] = centroidOf(parts[i].ndt_source);
  // Views the first level placed only from a turned start: the second
  // level aligns them also from where they stood (alignView's `also_from`).
  std::vector<std::uint8_t> retried(n, 0);
  for (std::size_t level_index = 0; level_index < params.model_alignment_resolutions.size(); ++level_index) {
    const double resolution = params.model_alignment_resolutions[level_index];
    const ndt::NdtParameters level = alignmentLevel(params, resolution);
    std::vector<Eigen::Isometry3d> next = poses;
    std::vector<std::uint8_t> kept(n, 0);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
      if (parts[i].ndt_source.empty()) return;
      const PointCloud others = modelOfViews(params, resolution, parts, poses, [i](std::size_t j) { return j != i; });
      try {
        const ndt::NdtTarget target(others, level);
        const std::optional<ViewAlignment> aligned =
            alignView(params, target, resolution, reported[i], reduced[i], normals[i], parts[i].ndt_source,
                      centroids[i], poses[i],
                      level_index == 1 && retried[i] ? std::optional<Eigen::Isometry3d>(start[i]) : std::nullopt);
        if (aligned) {
          next[i] = aligned->pose;
          kept[i] = 1;
          if (level_index == 0 && aligned->retried) retried[i] = 1;
        }
      } catch (const InputError&) {
        // Too few points for any Gaussian: the view stays where it is.
      }
    });
    poses = std::move(next);
    result.model_alignment_accepted.push_back(static_cast<std::size_t>(std::count(kept.begin(), kept.end(), 1)));
    placed = kept;
  }
  recordAlignmentMoves(parts, start, poses, result);
}

// Why a view counts as apart (viewsApart); 0: it does not.
constexpr std::uint8_t kApartAlone = 1;          // few of its cubes shared with any other view
constexpr std::uint8_t kOutsideLinkedGroup = 2;  // outside the largest group of linked views

// The views the graph left apart from the others (view_overlap.hpp), and
// why: few of their cubes shared with any other view, or outside the
// largest group of linked views when that group holds most of them.
// `points`: each view's points (an empty view is never apart).
std::vector<std::uint8_t> viewsApart(const SequenceRegistrationParameters& params, const CubeOverlap& overlap,
                                     const std::vector<std::vector<Eigen::Vector3d>>& points) {
  const std::size_t n = points.size();
  std::vector<std::uint8_t> apart(n, 0);
  std::vector<double> held;
  for (std::size_t i = 0; i < n; ++i)
    if (!points[i].empty()) held.push_back(overlap.shared[i]);
  if (held.empty()) return apart;
  std::nth_element(held.begin(), held.begin() + static_cast<std::ptrdiff_t>(held.size() / 2), held.end());
  const double median = held[held.size() / 2];
  // Well below its peers too: a recording whose views barely overlap (a
  // few views far apart) has every share low.
  for (std::size_t i = 0; i < n; ++i)
    if (!points[i].empty() && overlap.shared[i] < params.reseat_min_shared_cubes && overlap.shared[i] < 0.5 * median)
      apart[i] = kApartAlone;
  // Views off together: outside the largest group of linked pairs, when
  // that group holds most of the views (several small groups say only that
  // the views are far apart, not which of them are off).
  if (params.reseat_min_pair_cubes > 0) {
    const std::vector<std::uint8_t> linked = largestLinkedGroup(overlap.pair, params.reseat_min_pair_cubes);
    std::size_t in_group = 0;
    for (std::size_t i = 0; i < n; ++i) in_group += !points[i].empty() && linked[i];
    if (2 * in_group > held.size())
      for (std::size_t i = 0; i < n; ++i)
        if (!points[i].empty() && !linked[i] && !apart[i]) apart[i] = kOutsideLinkedGroup;
  }
  return apart;
}

// After the pose graph: the views to seat again are those the model
// alignment's last level left unplaced and those the graph left apart from
// the others (view_overlap.hpp). Views apart together (linked to each
// other, not to the rest) move as one rigid group, so that what agrees
// within the group stays as the graph made it; any other view is a group
// of its own. Each group is aligned again, through the same levels (the
// first with its turned starts), against the views kept, where the graph
// put them (they now hold the frame, view 0 included when it is
// re-seated). The graph's pose competes at the finest level (alignView's
// `also_from`): the better-scoring start wins, refined against the sharp
// model either way, so a group already home stays home. A group still
// apart after that is searched for: the two finest levels from a grid of
// starts around its graph pose (`reseat_search_step`), the best final
// score kept. A group left unseated is tried again in a later pass
// (`reseat_passes`) against the model grown by the groups seated.
void reseatViews(const SequenceRegistrationParameters& params, const std::vector<Eigen::Isometry3d>& reported,
                 const std::vector<std::vector<Eigen::Vector3d>>& reduced,
                 const std::vector<std::vector<Eigen::Vector3d>>& normals, const std::vector<ScanParts>& parts,
                 const std::vector<std::uint8_t>& placed, std::vector<Eigen::Isometry3d>& poses,
                 SequenceRegistrationResult& result) {
  const std::size_t n = poses.size();
  const bool overlaps = params.reseat_min_shared_cubes > 0 || params.reseat_min_pair_cubes > 0;
  CubeOverlap overlap;
  std::vector<std::uint8_t> apart(n, 0);
  if (overlaps) {
    std::vector<std::vector<Eigen::Vector3d>> points(n);
    for (std::size_t i = 0; i < n; ++i) points[i] = parts[i].model_points;
    overlap = cubeOverlap(points, poses, params.reseat_overlap_cube);
    apart = viewsApart(params, overlap, points);
  }
  std::vector<std::size_t> chosen;
  std::size_t kept_count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (parts[i].ndt_source.empty()) continue;
    if (placed[i] && !apart[i]) ++kept_count;
    else chosen.push_back(i);
  }
  // The views kept must outnumber the others for their union to be the
  // object; otherwise the graph's poses are all there is.
  if (chosen.empty() || kept_count <= chosen.size()) return;
  // The views the groups are aligned against: those kept, and after a
  // pass the groups it seated.
  std::vector<std::uint8_t> in_model(n, 0);
  for (std::size_t j = 0; j < n; ++j) in_model[j] = placed[j] != 0 && apart[j] == 0;
  auto kept = [&](std::size_t j) { return in_model[j] != 0; };
  // The groups: the views outside the largest linked group, linked among
  // themselves; every other view chosen (unplaced, or apart by its own
  // share) is a group of its own, so that a view off is never tied to one
  // in place.
  std::vector<std::vector<std::size_t>> groups;
  std::vector<std::size_t> outside;
  for (std::size_t i : chosen)
    if (apart[i] == kOutsideLinkedGroup) outside.push_back(i);
    else groups.push_back({i});
  if (!outside.empty())
    for (std::vector<std::size_t>& g : linkedGroups(overlap.pair, outside, params.reseat_min_pair_cubes))
      groups.push_back(std::move(g));
  std::sort(groups.begin(), groups.end());
  const std::size_t levels = params.model_alignment_resolutions.size();
  // The grid's starts: offsets of the group's points along the world axes,
  // nearest first (ties in index order), so that the result does not
  // depend on how the threads share them.
  std::vector<Eigen::Vector3d> offsets;
  const int reach = params.reseat_search_steps;
  if (params.reseat_search_step > 0 && levels >= 2)
    for (int a = -reach; a <= reach; ++a)
      for (int b = -reach; b <= reach; ++b)
        for (int c = -reach; c <= reach; ++c)
          if (a || b || c) offsets.emplace_back(Eigen::Vector3d(a, b, c) * params.reseat_search_step);
  std::stable_sort(offsets.begin(), offsets.end(),
                   [](const Eigen::Vector3d& x, const Eigen::Vector3d& y) { return x.norm() < y.norm(); });
  std::vector<std::uint8_t> seated(groups.size(), 0), ever_searched(groups.size(), 0);
  // A group that shares too little with the views kept finds no start
  // that scores (three neighbouring views whose only partners are another
  // group left apart): a second pass aligns it against the kept views and
  // the groups the first pass seated.
  for (int pass = 0; pass < params.reseat_passes; ++pass) {
    std::vector<std::size_t> pending;
    for (std::size_t g = 0; g < groups.size(); ++g)
      if (!seated[g]) pending.push_back(g);
    if (pending.empty()) break;
    // One model per level, shared by every group re-seated (NdtTarget is
    // read-only once built).
    std::vector<std::optional<ndt::NdtTarget>> targets(levels);
    tbb::parallel_for(std::size_t{0}, levels, [&](std::size_t level) {
      const double resolution = params.model_alignment_resolutions[level];
      const PointCloud others = modelOfViews(params, resolution, parts, poses, kept);
      try {
        targets[level].emplace(others, alignmentLevel(params, resolution));
      } catch (const InputError&) {
        // Too few points for any Gaussian: no re-seat at this level.
      }
    });
    if (!targets.back()) break;
    if (pass == 0) result.reseat_tried = chosen.size();
    // What a group still apart is measured against (only when it may be searched for).
    OccupiedCubes others(params.reseat_overlap_cube);
    if (!offsets.empty())
      for (std::size_t j = 0; j < n; ++j)
        if (kept(j)) others.add(parts[j].model_points, poses[j]);
    std::vector<std::optional<ViewAlignment>> aligned_last(pending.size());
    std::vector<std::uint8_t> searched(pending.size(), 0);
    tbb::parallel_for(std::size_t{0}, pending.size(), [&](std::size_t q) {
      const std::vector<std::size_t>& group = groups[pending[q]];
      const std::size_t first = group.front();
      // The group's points in its first view's frame, where the graph put them.
      std::vector<Eigen::Vector3d> source, cubes, points, point_normals;
      for (std::size_t m : group) {
        const Eigen::Isometry3d to_first = poses[first].inverse() * poses[m];
        for (const Eigen::Vector3d& p : parts[m].ndt_source) source.push_back(to_first * p);
        for (const Eigen::Vector3d& p : parts[m].model_points) cubes.push_back(to_first * p);
        for (const Eigen::Vector3d& p : reduced[m]) points.push_back(to_first * p);
        // A member without normals adds zero ones, which observe nothing.
        if (normals[m].size() == reduced[m].size())
          for (const Eigen::Vector3d& v : normals[m]) point_normals.push_back(to_first.linear() * v);
        else
          point_normals.resize(points.size(), Eigen::Vector3d::Zero());
      }
      const Eigen::Vector3d centroid = centroidOf(source);
      auto align = [&](std::size_t level, const Eigen::Isometry3d& from,
                       const std::optional<Eigen::Isometry3d>& also_from) -> std::optional<ViewAlignment> {
        try {
          return alignView(params, *targets[level], params.model_alignment_resolutions[level], reported[first], points,
                           point_normals, source, centroid, from, also_from);
        } catch (const InputError&) {
          return std::nullopt;  // no point of the group near the model from there
        }
      };
      Eigen::Isometry3d pose = poses[first];
      for (std::size_t level = 0; level < levels; ++level) {
        if (!targets[level]) continue;
        const bool last = level + 1 == levels;
        const std::optional<ViewAlignment> aligned =
            align(level, pose, last ? std::optional<Eigen::Isometry3d>(poses[first]) : std::nullopt);
        if (aligned) pose = aligned->pose;
        if (last) aligned_last[q] = aligned;  // neither start scoring: the graph's pose stays
      }
      if (offsets.empty() || !targets[levels - 2]) return;
      const Eigen::Isometry3d& walked = aligned_last[q] ? aligned_last[q]->pose : poses[first];
      if (others.shareOf(cubes, walked) >= params.reseat_min_shared_cubes) return;
      searched[q] = 1;
      std::vector<std::optional<ViewAlignment>> found(offsets.size());
      tbb::parallel_for(std::size_t{0}, offsets.size(), [&](std::size_t k) {
        Eigen::Isometry3d start = poses[first];
        start.pretranslate(offsets[k]);
        const std::optional<ViewAlignment> coarse = align(levels - 2, start, std::nullopt);
        if (coarse) found[k] = align(levels - 1, coarse->pose, std::nullopt);
      });
      for (std::optional<ViewAlignment>& f : found)
        if (f && (!aligned_last[q] || f->score > aligned_last[q]->score)) aligned_last[q] = f;
    });
    for (std::size_t q = 0; q < pending.size(); ++q) {
      const std::size_t g = pending[q];
      if (searched[q]) ever_searched[g] = 1;
      if (!aligned_last[q]) continue;
      const Eigen::Isometry3d correction = aligned_last[q]->pose * poses[groups[g].front()].inverse();
      // Each member within the model alignment's limits from its own
      // reported pose (the group's were judged from its first view's).
      const bool within = std::all_of(groups[g].begin(), groups[g].end(), [&](std::size_t m) {
        const Eigen::Vector3d centroid = centroidOf(parts[m].ndt_source);
        const Eigen::Isometry3d moved = correction * poses[m];
        return (moved * centroid - reported[m] * centroid).norm() <= params.model_alignment_max_translation &&
               rotationAngle(moved * reported[m].inverse()) <= params.model_alignment_max_rotation;
      });
      if (!within) continue;
      seated[g] = 1;
      for (std::size_t m : groups[g]) poses[m] = correction * poses[m];
      if (!aligned_last[q]->from_also) result.reseat_moved += groups[g].size();
    }
    // Only what this pass seated can help the groups it left.
    bool grew = false;
    for (std::size_t g : pending)
      if (seated[g])
        for (std::size_t m : groups[g])
          if (!in_model[m]) {
            in_model[m] = 1;
            grew = true;
          }
    if (!grew) break;
  }
  for (std::size_t g = 0; g < groups.size(); ++g)
    if (ever_searched[g]) result.reseat_searched += groups[g].size();
}

}  // namespace

void SequenceRegistration::Impl::prepare(std::size_t i, ScanParts& out) {
  try {
    out.ndt_target.emplace(positionsOnly(reduced[i]), coarseNdt());
  } catch (const InputError&) {
    // Too few points for any Gaussian: the scan's pairs fail.
  }
  if (normals[i].size() != reduced[i].size()) normals[i] = surfaceNormals(reduced[i]);
  VoxelModel coarse(params.pair_ndt_source_voxel_size);
  coarse.add(reduced[i], Eigen::Isometry3d::Identity());
  out.ndt_source = coarse.centroids().positions;
  if (!params.model_alignment_resolutions.empty()) {
    VoxelModel cubes(kModelAlignmentVoxel);
    cubes.add(reduced[i], Eigen::Isometry3d::Identity());
    out.model_points = cubes.centroids().positions;
  }
  if (!params.icp_refinement || reduced[i].size() < 3) return;
  std::optional<std::vector<Eigen::Vector3d>> tangents = normals[i];
  if (tangents->size() != reduced[i].size()) tangents = tangentNormals(reduced[i], params.normals_in_index_order);
  if (!tangents) return;
  out.icp_target.emplace(reduced[i], std::move(*tangents));
  if (params.icp_source_voxel_size > 0) {
    VoxelModel cubes(params.icp_source_voxel_size);
    cubes.add(reduced[i], Eigen::Isometry3d::Identity());
    out.icp_source = cubes.centroids().positions;
  } else {
    out.icp_source = reduced[i];
  }
  // A fixed stride keeps the points spread over the view (the cubes are
  // in key order) and the cost bounded for dense views.
  const std::size_t cap = std::max<std::size_t>(params.icp_max_source_points, 1);
  if (out.icp_source.size() > cap) {
    const double stride = double(out.icp_source.size()) / double(cap);
    std::vector<Eigen::Vector3d> kept;
    kept.reserve(cap);
    for (std::size_t k = 0; k < cap; ++k) kept.push_back(out.icp_source[static_cast<std::size_t>(k * stride)]);
    out.icp_source = std::move(kept);
  }
}

void SequenceRegistration::Impl::registerPair(const std::vector<ScanParts>& all,
                                              const std::vector<Eigen::Isometry3d>& poses, int round,
                                              bool both_placed, PairRegistrationRecord& pair, Matrix6d& hessian,
                                              Matrix6d& projector) const {
  // The NDT's wide basin is needed only from the robot's poses; later
  // rounds start from the graph's, within the ICP's reach.
  const bool coarse_start = round == 0 && !(both_placed && !params.pair_ndt_for_placed_views);
  attemptPair(all, poses, round, coarse_start, pair, hessian, projector);
}

void SequenceRegistration::Impl::retryPairCoarse(const std::vector<ScanParts>& all,
                                                 const std::vector<Eigen::Isometry3d>& poses,
                                                 PairRegistrationRecord& pair, Matrix6d& hessian,
                                                 Matrix6d& projector) const {
  PairRegistrationRecord again = unregisteredPair(pair.from, pair.to, pair.overlap, pair.round);
  again.retried_coarse = true;
  hessian.setZero();
  projector.setIdentity();
  attemptPair(all, poses, 0, true, again, hessian, projector);
  pair = again;
}

void SequenceRegistration::Impl::retryBridgingPairs(const std::vector<ScanParts>& all,
                                                    const std::vector<Eigen::Isometry3d>& poses,
                                                    const std::vector<std::uint8_t>& placed,
                                                    std::vector<PairRegistrationRecord>& pairs,
                                                    std::vector<Matrix6d>& hessians, std::vector<Matrix6d>& projectors,
                                                    SequenceRegistrationResult& result) const {
  DisjointSets components = linkedViews(pairs, poses.size());
  // Only a pair between two components, rejected because the ICP matched
  // too little of it (its views beyond the ICP's reach), is worth the
  // NDT's wider basin. Elsewhere the graph holds the views together
  // already: on nine real views 40 deg apart every run rejects one to
  // three pairs 80-120 deg apart for too little overlap, and their NDT
  // (+10 % time) fails again; a pair the ICP took somewhere the judge
  // refused (a symmetric object's slide) would slide again.
  std::vector<std::size_t> bridging;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const PairRegistrationRecord& pair = pairs[k];
    if (!pair.accepted && placed[pair.from] && placed[pair.to] &&
        pair.icp_inlier_fraction < params.min_icp_inlier_fraction &&
        components.find(std::uint32_t(pair.from)) != components.find(std::uint32_t(pair.to)))
      bridging.push_back(k);
  }
  tbb::parallel_for(std::size_t{0}, bridging.size(), [&](std::size_t q) {
    const std::size_t k = bridging[q];
    retryPairCoarse(all, poses, pairs[k], hessians[k], projectors[k]);
  });
  result.pairs_retried_coarse += bridging.size();
  for (std::size_t k : bridging) result.pairs_retried_accepted += pairs[k].accepted;
}

SequenceRegistration::Impl::UnsettledRound SequenceRegistration::Impl::linkUnsettledGroups(
    const std::vector<ScanParts>& all, const std::vector<Eigen::Isometry3d>& poses, int round,
    const std::vector<PairRegistrationRecord>& pairs, const std::vector<Matrix6d>& hessians,
    const std::vector<Matrix6d>& projectors) const {
  // Every pair of the last round stays, an accepted one with its
  // measurement (a relative pose does not depend on where the graph put
  // the views; measured again, a symmetric object's pair may slide). A
  // pair that would join views no accepted pair links, the last round's
  // rejected ones and those chosen anew at the graph's poses, is
  // registered from there.
  UnsettledRound out{pairs, hessians, projectors};
  DisjointSets linked = linkedViews(pairs, poses.size());
  std::vector<std::uint32_t> component(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) component[i] = linked.find(std::uint32_t(i));
  const auto joins = [&](std::size_t a, std::size_t b) { return component[a] != component[b]; };
  std::set<std::pair<std::size_t, std::size_t>> present;
  std::vector<std::size_t> fresh;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    present.insert({pairs[k].from, pairs[k].to});
    if (!pairs[k].accepted && joins(pairs[k].from, pairs[k].to)) fresh.push_back(k);
  }
  for (const auto& [pair, overlap] : choosePairs(reduced, poses, params)) {
    if (present.count(pair) || !joins(pair.first, pair.second)) continue;
    out.pairs.push_back(unregisteredPair(pair.first, pair.second, overlap, round));
    out.hessians.push_back(Matrix6d::Zero());
    out.projectors.push_back(Matrix6d::Identity());
    fresh.push_back(out.pairs.size() - 1);
  }
  for (PairRegistrationRecord& pair : out.pairs) pair.round = round;
  tbb::parallel_for(std::size_t{0}, fresh.size(), [&](std::size_t q) {
    const std::size_t k = fresh[q];
    PairRegistrationRecord again = unregisteredPair(out.pairs[k].from, out.pairs[k].to, out.pairs[k].overlap, round);
    out.hessians[k].setZero();
    out.projectors[k].setIdentity();
    // The ICP alone, from the graph's relative pose (the later rounds'
    // schedule).
    attemptPair(all, poses, round, false, again, out.hessians[k], out.projectors[k]);
    out.pairs[k] = again;
  });
  // A link with a direction its surface does not fix (a cup's pairs turn
  // freely about its axis) does not place one group against the other: on
  // the simulated cups such links were accepted 10-150 mm from the graph's
  // relative poses and made the views worse.
  for (std::size_t k : fresh)
    if (out.pairs[k].accepted && out.pairs[k].degenerate_directions > 0) {
      out.pairs[k].accepted = false;
      out.pairs[k].rejection = std::to_string(out.pairs[k].degenerate_directions) +
                               " directions its surface does not fix: an unsettled round takes only full links";
    }
  out.registered = fresh.size();
  for (std::size_t k : fresh) out.accepted_links += out.pairs[k].accepted;
  return out;
}

void SequenceRegistration::Impl::attemptPair(const std::vector<ScanParts>& all,
                                             const std::vector<Eigen::Isometry3d>& poses, int round, bool coarse_start,
                                             PairRegistrationRecord& pair, Matrix6d& hessian,
                                             Matrix6d& projector) const {
  const Eigen::Isometry3d implied = poses[pair.from].inverse() * poses[pair.to];
  const bool fine = params.icp_refinement && all[pair.from].icp_target && !all[pair.to].icp_source.empty();
  try {
    ndt::NdtResult estimate;
    estimate.pose = implied;
    if ((coarse_start && params.pair_ndt) || !fine) {
      if (!all[pair.from].ndt_target) throw InputError("scan " + std::to_string(pair.from), "", "too few points for NDT");
      const std::vector<Eigen::Vector3d>& source = fine ? all[pair.to].ndt_source : reduced[pair.to];
      estimate = ndt::registerNdt(positionsOnly(source), *all[pair.from].ndt_target, implied, coarseNdt());
      hessian = estimate.hessian;
      pair.normalized_score = estimate.normalized_score;
    } else {
      estimate.normalized_score = 1.0;
    }
    if (fine) {
      // Later rounds start within a millimetre or two: the coarse stages
      // would only repeat the last one's work.
      PointToPlaneIcpParameters icp_params = params.icp;
      if (round > 0 && icp_params.max_distances.size() > 2)
        icp_params.max_distances.erase(icp_params.max_distances.begin(), icp_params.max_distances.end() - 2);
      if (coarse_start && !params.pair_ndt)
        icp_params.max_distances.insert(icp_params.max_distances.begin(), params.icp_wide_distances.begin(),
                                        params.icp_wide_distances.end());
      const PointToPlaneIcpResult icp =
          registerPointToPlane(all[pair.to].icp_source, *all[pair.from].icp_target, estimate.pose, icp_params);
      pair.icp_inlier_fraction = icp.inlier_fraction;
      pair.icp_rms_m = icp.rms_m;
      if (icp.failed || icp.inlier_fraction < params.min_icp_inlier_fraction) {
        pair.rejection = "ICP matched " + std::to_string(icp.correspondences) + " points (" +
                         std::to_string(100.0 * icp.inlier_fraction) + " %), too little overlap";
      } else {
        estimate.pose = icp.pose;
        // The residuals' variance turns sum J^T J into an information.
        const double variance = std::max(icp.rms_m * icp.rms_m, 1e-12);
        hessian = icp.hessian / variance;
      }
    }
    const Observability o = scanObservability(reduced[pair.to], normals[pair.to], implied, params.degeneracy_ratio);
    if (params.degeneracy_ratio > 0) {
      remapDegenerate(estimate, implied, o);
      projector = o.projector;
    }
    pair.degenerate_directions = o.degenerate_directions;
    pair.weakest_direction_ratio = o.weakest_ratio;
    if (pair.rejection.empty()) pair.rejection = judge(estimate, implied, reduced[pair.to], "the scan-to-model poses");
    const Eigen::Isometry3d discrepancy = implied.inverse() * estimate.pose;
    pair.discrepancy_translation_m = discrepancy.translation().norm();
    pair.discrepancy_rotation_rad = rotationAngle(discrepancy);
    if (pair.rejection.empty()) {
      pair.accepted = true;
      pair.measurement = estimate.pose;
    }
  } catch (const InputError& e) {
    pair.rejection = std::string("NDT: ") + e.what();
  }
}

void SequenceRegistration::Impl::alignAndPair(std::size_t i) {
  parts.emplace_back();
  prepare(i, parts.back());
  const ScanRegistrationRecord& record = records[i];
  Eigen::Isometry3d pose = record.model_pose;
  level_kept.resize(params.model_alignment_resolutions.size(), 0);
  // The earlier views must already cover enough of this one: where they
  // hardly do (the first view of a side not seen yet) the NDT slides along
  // what little they share (45 mm on a simulated SR4000 view covered to
  // 26 %). Such a view keeps its reported pose; its pairs' NDT starts from
  // there.
  std::vector<std::int64_t> coarse_cubes;
  for (const Eigen::Vector3d& p : parts[i].ndt_source) coarse_cubes.push_back(cubeKey(pose * p, kCoverageCube));
  std::sort(coarse_cubes.begin(), coarse_cubes.end());
  coarse_cubes.erase(std::unique(coarse_cubes.begin(), coarse_cubes.end()), coarse_cubes.end());
  std::size_t covered = 0;
  for (std::int64_t key : coarse_cubes) covered += std::binary_search(covered_cubes.begin(), covered_cubes.end(), key);
  const bool covered_enough =
      !coarse_cubes.empty() && double(covered) >= params.min_pair_overlap * double(coarse_cubes.size());
  if (i > 0 && covered_enough) {
    const Eigen::Vector3d centroid = centroidOf(parts[i].ndt_source);
    const Eigen::Isometry3d unturned_start = pose;
    bool retried = false;  // placed by a turned start at the first level: judged again at the second
    for (std::size_t l = 0; l < params.model_alignment_resolutions.size(); ++l) {
      const double resolution = params.model_alignment_resolutions[l];
      const PointCloud earlier = modelOfViews(params, resolution, parts, aligned, [i](std::size_t j) { return j < i; });
      try {
        const ndt::NdtTarget target(earlier, alignmentLevel(params, resolution));
        const std::optional<ViewAlignment> moved =
            alignView(params, target, resolution, record.initial_pose, reduced[i], normals[i], parts[i].ndt_source,
                      centroid, pose,
                      l == 1 && retried ? std::optional<Eigen::Isometry3d>(unturned_start) : std::nullopt);
        if (moved) {
          pose = moved->pose;
          ++level_kept[l];
          if (l == 0) retried = moved->retried;
        }
      } catch (const InputError&) {
        // Too few points for any Gaussian: the view stays where it is.
      }
    }
  }
  aligned.push_back(pose);
  cubes.push_back(occupiedCubes(reduced[i], pose));
  for (const Eigen::Vector3d& p : parts[i].ndt_source) covered_cubes.push_back(cubeKey(pose * p, kCoverageCube));
  std::sort(covered_cubes.begin(), covered_cubes.end());
  covered_cubes.erase(std::unique(covered_cubes.begin(), covered_cubes.end()), covered_cubes.end());
  if (i == 0) return;

  // Its best-overlapping earlier views, and the previous one.
  std::vector<std::pair<double, std::size_t>> partners;
  for (std::size_t j = 0; j < i; ++j) {
    const double overlap = overlapFraction(cubes[j], cubes[i]);
    if (overlap >= params.min_pair_overlap) partners.emplace_back(-overlap, j);
  }
  std::sort(partners.begin(), partners.end());
  if (partners.size() > static_cast<std::size_t>(std::max(0, params.max_partners)))
    partners.resize(static_cast<std::size_t>(std::max(0, params.max_partners)));
  std::map<std::size_t, double> chosen;
  for (const auto& [negative_overlap, j] : partners) chosen[j] = -negative_overlap;
  if (params.sequence_pairs) chosen.emplace(i - 1, overlapFraction(cubes[i - 1], cubes[i]));
  const std::size_t first = early_pairs.size();
  for (const auto& [j, overlap] : chosen) {
    PairRegistrationRecord pair;
    pair.from = j;
    pair.to = i;
    pair.overlap = overlap;
    early_pairs.push_back(pair);
  }
  early_hessians.resize(early_pairs.size(), Matrix6d::Zero());
  early_projectors.resize(early_pairs.size(), Matrix6d::Identity());
  tbb::parallel_for(first, early_pairs.size(), [&](std::size_t k) {
    registerPair(parts, aligned, 0, false, early_pairs[k], early_hessians[k], early_projectors[k]);
  });
}

void SequenceRegistration::Impl::firstRoundPairs(std::vector<PairRegistrationRecord>& pairs,
                                                 std::vector<Matrix6d>& hessians,
                                                 std::vector<Matrix6d>& projectors) const {
  const std::size_t n = records.size();
  pairs = early_pairs;
  hessians = early_hessians;
  projectors = early_projectors;
  const bool has_loop = std::any_of(pairs.begin(), pairs.end(),
                                    [&](const PairRegistrationRecord& p) { return p.from == 0 && p.to == n - 1; });
  if (params.loop_closure && n >= 3 && !has_loop) {
    // The loop closure: the last view against the first, known only now.
    PairRegistrationRecord pair;
    pair.from = 0;
    pair.to = n - 1;
    pair.overlap = overlapFraction(cubes[0], cubes[n - 1]);
    Matrix6d hessian = Matrix6d::Zero(), projector = Matrix6d::Identity();
    registerPair(parts, aligned, 0, false, pair, hessian, projector);
    pairs.push_back(pair);
    hessians.push_back(hessian);
    projectors.push_back(projector);
  }
  // In the batch's order (by view pair), so that the graph is built alike.
  std::vector<std::size_t> order(pairs.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::make_pair(pairs[a].from, pairs[a].to) < std::make_pair(pairs[b].from, pairs[b].to);
  });
  std::vector<PairRegistrationRecord> sorted_pairs;
  std::vector<Matrix6d> sorted_hessians, sorted_projectors;
  for (std::size_t k : order) {
    sorted_pairs.push_back(pairs[k]);
    sorted_hessians.push_back(hessians[k]);
    sorted_projectors.push_back(projectors[k]);
  }
  pairs = std::move(sorted_pairs);
  hessians = std::move(sorted_hessians);
  projectors = std::move(sorted_projectors);
}

SequenceRegistrationResult SequenceRegistration::finish() {
  Impl& s = *impl_;
  if (s.finished) throw std::logic_error("SequenceRegistration::finish called twice");
  if (!s.broken.empty()) throw std::logic_error("SequenceRegistration::finish after a failed add(): " + s.broken);
  if (s.records.empty()) throw InputError("scan sequence", "", "no scans to register");
  // Incremental: more scans may follow, registered against these.
  if (!s.params.incremental) {
    s.finished = true;
    s.target.reset();
  }
  const auto start = Clock::now();
  const std::size_t n = s.records.size();
  SequenceRegistrationResult result;

  std::vector<ScanParts> built;
  if (!s.params.incremental) {
    built.resize(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) { s.prepare(i, built[i]); });
  }
  const std::vector<ScanParts>& parts = s.params.incremental ? s.parts : built;

  std::vector<Eigen::Isometry3d> poses;
  for (const ScanRegistrationRecord& r : s.records) poses.push_back(r.model_pose);
  // The model alignment's levels for this object (batch: all its views are here).
  SequenceRegistrationParameters chosen = s.params;
  if (!s.params.incremental && !s.params.model_alignment_resolutions.empty()) {
    std::vector<const std::vector<Eigen::Vector3d>*> cubes;
    for (const ScanParts& p : parts) cubes.push_back(&p.model_points);
    result.model_spread_m = medianViewSpread(cubes);
    chosen.model_alignment_resolutions = modelAlignmentLevels(
        s.params.model_alignment_resolutions, s.params.model_alignment_max_cell_to_spread, result.model_spread_m);
  }
  const SequenceRegistrationParameters& params = chosen;
  result.model_alignment_resolutions = params.model_alignment_resolutions;
  result.stage_times.prepare_ms = millisecondsSince(start);
  double alignment_sigma_t = 0.0, alignment_sigma_r = 0.0;  // per view, robust, from the model alignment
  if (params.incremental && !params.model_alignment_resolutions.empty()) poses = s.aligned;
  // Views the model alignment's last level placed (the batch path only).
  std::vector<std::uint8_t> placed(n, 0);
  std::vector<Eigen::Isometry3d> reported;  // the robot's poses: the model alignment's limits
  for (const ScanRegistrationRecord& r : s.records) reported.push_back(r.initial_pose);
  // Each view's points' centroid (none without points): where its moves are measured.
  std::vector<std::optional<Eigen::Vector3d>> centroids(n);
  for (std::size_t i = 0; i < n; ++i)
    if (!parts[i].ndt_source.empty()) centroids[i] = centroidOf(parts[i].ndt_source);
  const auto alignment_start = Clock::now();
  if (n >= 3 && !params.model_alignment_resolutions.empty()) {
    if (params.incremental) {
      result.model_alignment_accepted = s.level_kept;
      std::vector<Eigen::Isometry3d> before;
      for (const ScanRegistrationRecord& r : s.records) before.push_back(r.model_pose);
      recordAlignmentMoves(parts, before, poses, result);
    } else {
      alignToOthers(params, reported, s.reduced, s.normals, parts, poses, placed, result);
    }
    // Without the robot's priors the first scan holds the frame (the pose
    // graph fixes it): the views moved together, so move them back as one.
    const bool gauge_from_priors =
        params.prior_sigma_translation > 0 ||
        std::any_of(s.priors.begin(), s.priors.end(), [](const std::optional<PosePrior>& p) { return p.has_value(); });
    if (!gauge_from_priors) {
      const Eigen::Isometry3d back = s.records.front().model_pose * poses.front().inverse();
      for (Eigen::Isometry3d& pose : poses) pose = back * pose;
    }
    // How far the robot placed each view from where the others put it: the
    // robot's per-view error as its prior edges see it (sensor frame). On
    // an object whose consecutive pairs are all degenerate (a cup, a
    // bottle) the pairs cannot measure it, and the stated sigmas of an arm
    // would pin a mobile robot's views where it reported them.
    // Measured where it matters and where the alignment is sure of it: the
    // move of the view's points (a spin about a round object's axis, which
    // the alignment leaves uncertain, hardly moves them); the rotation sigma
    // is the one that moves them as far at their distance from the sensor.
    std::vector<double> moves;
    double distance = 0.0;
    std::size_t counted = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!centroids[i]) continue;
      const Eigen::Vector3d& centroid = *centroids[i];
      const Eigen::Vector3d move = poses[i] * centroid - reported[i] * centroid;
      for (int c = 0; c < 3; ++c) moves.push_back(std::abs(move(c)));
      distance += centroid.norm();
      ++counted;
    }
    if (moves.size() >= 9 && distance > 0) {
      alignment_sigma_t = robustSigma(moves);
      alignment_sigma_r = alignment_sigma_t / (distance / double(counted));
    }
  }
  result.stage_times.model_alignment_ms = millisecondsSince(alignment_start);
  int rounds = params.refinement_rounds > 0 ? params.refinement_rounds
               : params.incremental           ? 3
                                              : 2;
  const int last_allowed_round = params.refinement_rounds > 0 ? rounds : rounds + params.max_unsettled_rounds;
  // An unsettled round's pairs (`max_unsettled_rounds`), registered
  // before the round is run.
  std::optional<Impl::UnsettledRound> unsettled_round;
  for (int round = 0; round < rounds; ++round) {
    const auto pairs_start = Clock::now();
    std::vector<PairRegistrationRecord> pairs;
    std::vector<Matrix6d> hessians, projectors;
    if (round == 0 && params.incremental) {
      s.firstRoundPairs(pairs, hessians, projectors);
    } else if (unsettled_round) {
      pairs = std::move(unsettled_round->pairs);
      hessians = std::move(unsettled_round->hessians);
      projectors = std::move(unsettled_round->projectors);
      unsettled_round.reset();
    } else {
      const auto chosen = choosePairs(s.reduced, poses, params);
      pairs.reserve(chosen.size());
      for (const auto& [pair, overlap] : chosen) pairs.push_back(unregisteredPair(pair.first, pair.second, overlap, round));
      hessians.assign(pairs.size(), Matrix6d::Zero());
      projectors.assign(pairs.size(), Matrix6d::Identity());
      // Each pair is independent and deterministic: their order of
      // completion does not matter.
      tbb::parallel_for(std::size_t{0}, pairs.size(), [&](std::size_t k) {
        const bool both_placed = placed[pairs[k].from] && placed[pairs[k].to];
        s.registerPair(parts, poses, round, both_placed, pairs[k], hessians[k], projectors[k]);
      });
      if (round == 0 && params.pair_ndt_retry_rejected && !params.pair_ndt_for_placed_views)
        s.retryBridgingPairs(parts, poses, placed, pairs, hessians, projectors, result);
    }
    result.stage_times.pairs_ms += millisecondsSince(pairs_start);
    const auto graph_start = Clock::now();

    // How good the robot's own relative motions and poses are, measured by
    // the consecutive pairs (independent of the robot).
    double odometry_sigma_t = params.odometry_sigma_translation, odometry_sigma_r = params.odometry_sigma_rotation;
    double prior_sigma_t = params.prior_sigma_translation, prior_sigma_r = params.prior_sigma_rotation;
    {
      std::vector<double> translation, rotation;
      for (const PairRegistrationRecord& pair : pairs) {
        if (!pair.accepted || pair.to != pair.from + 1 || pair.degenerate_directions > 0) continue;
        const Eigen::Isometry3d odometry = s.records[pair.from].initial_pose.inverse() * s.records[pair.to].initial_pose;
        const Vector6d e = poseGraphEdgeError(Eigen::Isometry3d::Identity(), pair.measurement, odometry);
        for (int c = 0; c < 3; ++c) {
          translation.push_back(std::abs(e(c)));
          rotation.push_back(std::abs(e(3 + c)));
        }
      }
      if (translation.size() >= 9 || alignment_sigma_t > 0) {
        // The consecutive pairs when they measure it; else the model
        // alignment (independent per-view errors: a relative motion holds two).
        const bool from_pairs = translation.size() >= 9;
        result.measured_odometry_sigma_translation_m =
            from_pairs ? robustSigma(translation) : std::sqrt(2.0) * alignment_sigma_t;
        result.measured_odometry_sigma_rotation_rad =
            from_pairs ? robustSigma(rotation) : std::sqrt(2.0) * alignment_sigma_r;
        if (params.estimate_robot_precision) {
          if (odometry_sigma_t > 0 && odometry_sigma_r > 0) {
            odometry_sigma_t = std::max(odometry_sigma_t, result.measured_odometry_sigma_translation_m);
            odometry_sigma_r = std::max(odometry_sigma_r, result.measured_odometry_sigma_rotation_rad);
          }
          if (prior_sigma_t > 0 && prior_sigma_r > 0) {
            prior_sigma_t = std::max(prior_sigma_t, result.measured_odometry_sigma_translation_m / std::sqrt(2.0));
            prior_sigma_r = std::max(prior_sigma_r, result.measured_odometry_sigma_rotation_rad / std::sqrt(2.0));
          }
        }
      }
    }
    result.odometry_sigma_translation_m = odometry_sigma_t;
    result.odometry_sigma_rotation_rad = odometry_sigma_r;
    result.prior_sigma_translation_m = prior_sigma_t;
    result.prior_sigma_rotation_rad = prior_sigma_r;

    const bool priors = prior_sigma_t > 0;
    PoseGraph graph;
    graph.poses = poses;
    const Matrix6d registration_information =
        poseGraphInformation(params.registration_sigma_translation, params.registration_sigma_rotation);
    // One scale for all pairs, so that a pair that matched more points more
    // tightly keeps more weight: the median pair's best-constrained
    // translation gets `registration_sigma_translation`.
    std::vector<double> stiffness;
    for (std::size_t k = 0; k < pairs.size(); ++k)
      if (pairs[k].accepted) stiffness.push_back(translationStiffness(hessians[k]));
    double hessian_scale = 0.0;
    if (!stiffness.empty()) {
      std::nth_element(stiffness.begin(), stiffness.begin() + static_cast<std::ptrdiff_t>(stiffness.size() / 2),
                       stiffness.end());
      const double median = stiffness[stiffness.size() / 2];
      if (median > 0)
        hessian_scale = 1.0 / (params.registration_sigma_translation * params.registration_sigma_translation * median);
    }
    std::vector<std::size_t> pair_edges;
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      if (!pairs[k].accepted) continue;
      pair_edges.push_back(graph.edges.size());
      PoseGraphEdge edge;
      edge.from = pairs[k].from;
      edge.to = pairs[k].to;
      edge.measurement = pairs[k].measurement;
      edge.information = params.hessian_information
                             ? hessianInformation(hessians[k], projectors[k], pairs[k].measurement, hessian_scale)
                             : registration_information;
      graph.edges.push_back(edge);
    }
    // Without odometry, the scan-to-model chain as weak edges keeps every
    // scan connected when its pairs fail. With odometry it only adds the
    // sequential registration's drift (on the SR4000 cup: 1.09 instead of
    // 0.91 mm median error), so it is left out.
    const bool odometry = odometry_sigma_t > 0 && odometry_sigma_r > 0;
    for (std::size_t i = 1; i < n && !odometry; ++i) {
      PoseGraphEdge edge;
      edge.from = i - 1;
      edge.to = i;
      edge.measurement = s.records[i - 1].model_pose.inverse() * s.records[i].model_pose;
      const double weak = s.records[i].registered ? 10.0 : 20.0;
      edge.information =
          poseGraphInformation(weak * params.registration_sigma_translation, weak * params.registration_sigma_rotation);
      edge.robust = false;
      graph.edges.push_back(edge);
    }
    if (odometry) {
      const Matrix6d odometry_information = poseGraphInformation(odometry_sigma_t, odometry_sigma_r);
      for (std::size_t i = 1; i < n; ++i) {
        PoseGraphEdge edge;
        edge.from = i - 1;
        edge.to = i;
        edge.measurement = s.records[i - 1].initial_pose.inverse() * s.records[i].initial_pose;
        edge.information = odometry_information;
        edge.robust = false;
        graph.edges.push_back(edge);
      }
    }
    const bool extra_priors =
        std::any_of(s.priors.begin(), s.priors.end(), [](const std::optional<PosePrior>& p) { return p.has_value(); });
    if (priors || extra_priors) {
      // A world node at the identity, tied to every scan by its reported
      // pose and to those with another measurement of their pose by that one.
      const std::size_t world = n;
      graph.poses.push_back(Eigen::Isometry3d::Identity());
      for (std::size_t i = 0; i < n; ++i) {
        PoseGraphEdge edge;
        edge.from = world;
        edge.to = i;
        edge.robust = false;
        if (priors) {
          edge.measurement = s.records[i].initial_pose;
          edge.information = poseGraphInformation(prior_sigma_t, prior_sigma_r);
          graph.edges.push_back(edge);
        }
        if (s.priors[i]) {
          // Robust: an independent measurement (a board corner lattice
          // locked one square off, say) must not drag the whole graph.
          edge.measurement = s.priors[i]->pose;
          edge.information = poseGraphInformation(s.priors[i]->sigma_translation, s.priors[i]->sigma_rotation);
          edge.robust = true;
          graph.edges.push_back(edge);
        }
      }
      graph.fixed = {world};
    } else {
      graph.fixed = {0};
    }

    result.pairs = std::move(pairs);
    result.refinement_rounds = round + 1;
    if (n == 1 && !extra_priors) {
      poses = {s.records.front().model_pose};
      break;
    }
    PoseGraphResult solved = optimisePoseGraph(graph, params.graph);
    // How precise each group of edges really was on this data: the stated
    // sigmas are guesses (a Kinect pair is better than a SR4000 pair, a
    // mobile robot knows its pose worse than an arm). Variance component
    // estimation (pose_graph_variance.hpp) rescales the pairs, the robot's
    // priors and its odometry until each group's residuals match its
    // redundancy, solving the graph again each time.
    std::vector<int> groups(graph.edges.size(), -1);
    for (std::size_t e : pair_edges) groups[e] = 0;
    for (std::size_t e = 0; e < graph.edges.size(); ++e) {
      const PoseGraphEdge& edge = graph.edges[e];
      if (priors && edge.from == n && !edge.robust) groups[e] = 1;
      if (odometry && edge.from < n && edge.to == edge.from + 1 && !edge.robust) groups[e] = 2;
    }
    double factor = 1.0, prior_factor = 1.0, odometry_factor = 1.0;
    auto floorOf = [](double stated_t, double start_t, double stated_r, double start_r) {
      if (!(start_t > 0) || !(start_r > 0)) return 1.0;
      return std::min(1.0, std::max(std::pow(stated_t / start_t, 2), std::pow(stated_r / start_r, 2)));
    };
    const double prior_floor =
        floorOf(params.prior_sigma_translation, prior_sigma_t, params.prior_sigma_rotation, prior_sigma_r);
    const double odometry_floor =
        floorOf(params.odometry_sigma_translation, odometry_sigma_t, params.odometry_sigma_rotation, odometry_sigma_r);
    for (int v = 0; v < params.variance_rounds && pair_edges.size() >= 3; ++v) {
      std::array<double, 3> steps{1.0, 1.0, 1.0};
      // The pairs: their median chi-square against 6 degrees of freedom,
      // only ever weakening them. Their errors are largely systematic (a
      // depth camera's distortion repeats in every view), which their
      // mutual consistency cannot show: the redundancy estimate would make
      // them far stronger than they are (on the real PrimeSense bunny it
      // did, and the cloud got worse), so `registration_sigma_*` is a floor.
      std::vector<double> chi2;
      for (std::size_t e : pair_edges) {
        const PoseGraphEdge& edge = graph.edges[e];
        const Vector6d error = poseGraphEdgeError(solved.poses[edge.from], solved.poses[edge.to], edge.measurement);
        chi2.push_back(error.dot(edge.information * error));
      }
      std::nth_element(chi2.begin(), chi2.begin() + static_cast<std::ptrdiff_t>(chi2.size() / 2), chi2.end());
      steps[0] = std::clamp(chi2[chi2.size() / 2] / 5.35, 1.0 / factor, 1e2 / factor);
      // The robot's priors and odometry: their residuals against their
      // redundancy (too large a graph for the dense inverse: as stated).
      if (const auto components = estimateVarianceComponents(graph, solved, groups, 3))
        for (int g = 1; g < 3; ++g) steps[g] = std::clamp((*components)[g].variance_factor, 1e-2, 1e2);
      // The robot's groups stay between their stated sigmas and the ones the
      // consecutive pairs measured (which hold the pairs' own error too):
      // with wrong pairs among few, or noisy pairs (a ToF camera) against an
      // arm's precise odometry, unbounded factors feed on each other.
      steps[1] = std::clamp(steps[1], prior_floor / prior_factor, 1.0 / prior_factor);
      steps[2] = std::clamp(steps[2], odometry_floor / odometry_factor, 1.0 / odometry_factor);
      if (std::all_of(steps.begin(), steps.end(), [](double x) { return std::abs(std::log(x)) < std::log(1.2); }))
        break;
      factor *= steps[0];
      prior_factor *= steps[1];
      odometry_factor *= steps[2];
      for (std::size_t e = 0; e < graph.edges.size(); ++e)
        if (groups[e] >= 0) graph.edges[e].information /= steps[static_cast<std::size_t>(groups[e])];
      solved = optimisePoseGraph(graph, params.graph);
    }
    if (priors) {
      result.prior_sigma_translation_m *= std::sqrt(prior_factor);
      result.prior_sigma_rotation_rad *= std::sqrt(prior_factor);
    }
    if (odometry) {
      result.odometry_sigma_translation_m *= std::sqrt(odometry_factor);
      result.odometry_sigma_rotation_rad *= std::sqrt(odometry_factor);
    }
    result.pair_variance_factor = factor;
    std::vector<Eigen::Isometry3d> graph_poses(solved.poses.begin(),
                                               solved.poses.begin() + static_cast<std::ptrdiff_t>(n));
    const bool unsettled = round + 1 == rounds && rounds < last_allowed_round &&
                           !unsettledPairs(result.pairs, poses, graph_poses, centroids,
                                           params.min_icp_inlier_fraction, params.unsettled_pair_move)
                                .empty();
    poses = std::move(graph_poses);
    result.graph = solved.report;
    result.stage_times.graph_ms += millisecondsSince(graph_start);
    if (unsettled) {
      const auto unsettled_start = Clock::now();
      auto next = s.linkUnsettledGroups(parts, poses, round + 1, result.pairs, hessians, projectors);
      result.unsettled_pairs_registered += next.registered;
      result.unsettled_pairs_accepted += next.accepted_links;
      if (next.accepted_links > 0) {
        ++rounds;
        unsettled_round = std::move(next);
      }
      result.stage_times.pairs_ms += millisecondsSince(unsettled_start);
    }
  }
  if (params.reseat_unplaced_views && !params.incremental && n >= 3 && !params.model_alignment_resolutions.empty()) {
    const auto reseat_start = Clock::now();
    reseatViews(params, reported, s.reduced, s.normals, parts, placed, poses, result);
    result.stage_times.model_alignment_ms += millisecondsSince(reseat_start);
  }
  const auto joint_start = Clock::now();
  if (params.joint_refinement && n >= 2) {
    // Scaled as the ICP was for a sparser sensor (adaptResolutions).
    JointRefinementParameters joint = params.joint;
    const double scale = params.icp.kernel_width / PointToPlaneIcpParameters{}.kernel_width;
    if (scale > 1) {
      for (double& d : joint.max_distances) d *= scale;
      joint.kernel_width *= scale;
      joint.source_voxel_size *= scale;
    }
    // Each view may leave the graph's pose by about what the robot's motion
    // between views allows: an arm's odometry keeps the views where the
    // graph put them (with the default's weak hold they wander along what
    // the surface cannot see, a cup's axis: 5 mm from the truth on an arm's
    // recording), a mobile robot's lets them settle onto each other.
    if (result.odometry_sigma_translation_m > 0 && result.odometry_sigma_rotation_rad > 0) {
      joint.prior_sigma_translation = std::min(joint.prior_sigma_translation, result.odometry_sigma_translation_m);
      joint.prior_sigma_rotation = std::min(joint.prior_sigma_rotation, result.odometry_sigma_rotation_rad);
    }
    std::vector<std::vector<Eigen::Vector3d>> normals(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
      PointCloud cloud = positionsOnly(s.reduced[i]);
      ndt::NormalEstimationParameters facing;
      facing.viewpoint = Eigen::Vector3d::Zero();
      facing.radius = Length::metres(params.joint_normal_radius * std::max(1.0, scale));
      try {
        ndt::estimateNormals(cloud, facing);
        normals[i] = std::move(cloud.normals);
      } catch (const InputError&) {
        // Too few points: the view keeps its pose.
      }
    });
    std::vector<std::vector<Eigen::Vector3d>> points(n);
    for (std::size_t i = 0; i < n; ++i)
      if (normals[i].size() == s.reduced[i].size()) points[i] = s.reduced[i];
      else normals[i].clear();
    const JointRefinementResult refined = refineJointly(points, normals, poses, joint);
    result.joint_iterations = refined.iterations;
    result.joint_pairs = refined.pairs;
    result.joint_rms_m = refined.rms_m;
    result.joint_linked_view_pairs = refined.linked_view_pairs;
    // The graph's pairs of its last round, each once.
    int last_round = 0;
    for (const PairRegistrationRecord& pair : result.pairs) last_round = std::max(last_round, pair.round);
    std::vector<std::pair<std::size_t, std::size_t>> graph_pairs;
    for (const PairRegistrationRecord& pair : result.pairs)
      if (pair.accepted && pair.round == last_round) graph_pairs.emplace_back(pair.from, pair.to);
    result.joint_graph_view_pairs = countUnorderedPairs(std::move(graph_pairs));
    const double needed = params.joint_min_linked_pair_ratio * double(result.joint_graph_view_pairs);
    if (refined.iterations == 0) {
      result.joint_rejection = "no view has points to match";
    } else if (result.joint_graph_view_pairs == 0) {
      // Nothing to compare with: the pairs failed their overlap and ICP
      // checks, and the joint's matches are the same kind of evidence.
      result.joint_rejection = "the graph accepted no pair of views";
    } else if (double(refined.linked_view_pairs) < needed) {
      result.joint_rejection = "its face-on points linked " + std::to_string(refined.linked_view_pairs) +
                               " pairs of views, the graph " + std::to_string(result.joint_graph_view_pairs);
    } else {
      poses = refined.poses;
      result.joint_applied = true;
    }
  }
  result.stage_times.joint_ms = millisecondsSince(joint_start);
  result.poses = poses;

  const bool try_loop = params.loop_closure && n >= 3;
  if (try_loop) {
    LoopClosureRecord& loop = result.loop_closure;
    for (const PairRegistrationRecord& pair : result.pairs)
      if (pair.from == 0 && pair.to == n - 1) {
        loop.attempted = true;
        loop.accepted = pair.accepted;
        loop.rejection = pair.rejection;
        loop.from = 0;
        loop.to = n - 1;
        loop.normalized_score = pair.normalized_score;
        loop.discrepancy_translation_m = pair.discrepancy_translation_m;
        loop.discrepancy_rotation_rad = pair.discrepancy_rotation_rad;
      }
  }
  if (params.incremental)
    result.scans = s.records;
  else
    result.scans = std::move(s.records);
  result.model_points = s.model.size();
  result.resolutions = params.ndt.resolutions;
  result.first_scan_spacing_m = s.first_spacing;
  result.time_ms = s.time_ms + millisecondsSince(start);
  if (!params.incremental) {
    s.reduced = {};
    s.normals = {};
  }
  return result;
}

SequenceRegistrationResult registerScanSequence(const std::vector<PointCloud>& scans,
                                                const std::vector<Eigen::Isometry3d>& initial_poses,
                                                const SequenceRegistrationParameters& params) {
  if (scans.size() != initial_poses.size())
    throw InputError("scan sequence", "", std::to_string(scans.size()) + " scans but " +
                                              std::to_string(initial_poses.size()) + " initial poses");
  SequenceRegistration registration(params);
  for (std::size_t i = 0; i < scans.size(); ++i) registration.add(scans[i], initial_poses[i]);
  return registration.finish();
}

}  // namespace icrkit::reconstruction
