#include <icrkit/reconstruction/registration/pose_graph.hpp>

#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>

#include "cholmod_solver.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <string>

namespace icrkit::reconstruction {
namespace {

using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

constexpr std::size_t kNotFree = std::numeric_limits<std::size_t>::max();

Matrix3d skew(const Vector3d& v) {
  Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

// Through the quaternion so that the result is orthonormal to rounding
// whatever the angle, and exact to first order near zero.
Matrix3d expSO3(const Vector3d& theta) {
  const double angle = theta.norm();
  const double half_sinc = angle < 1e-4 ? 0.5 - angle * angle / 48.0 : std::sin(0.5 * angle) / angle;
  Quaterniond q(std::cos(0.5 * angle), half_sinc * theta.x(), half_sinc * theta.y(), half_sinc * theta.z());
  return q.normalized().toRotationMatrix();
}

// Rotation vector in [0, pi]; the quaternion route stays accurate near 0
// (where acos of the trace loses half the digits) and near pi.
Vector3d logSO3(const Matrix3d& rotation) {
  Quaterniond q(rotation);
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const Vector3d v = q.vec();
  const double n = v.norm();
  if (n < 1e-10) return (2.0 / q.w()) * v;
  return (2.0 * std::atan2(n, q.w()) / n) * v;
}

// Inverse right Jacobian of SO(3): Log(R Exp(d)) = Log(R) + Jr^-1 d + O(d^2).
Matrix3d rightJacobianInverse(const Vector3d& phi) {
  const double angle = phi.norm();
  const Matrix3d k = skew(phi);
  // 1/a^2 - (1 + cos a) / (2 a sin a), written with cot(a/2) so that it
  // stays finite up to a = pi (an edge error of half a turn).
  const double c = angle < 1e-4 ? 1.0 / 12.0 + angle * angle / 720.0
                                : 1.0 / (angle * angle) - std::cos(0.5 * angle) / (2.0 * angle * std::sin(0.5 * angle));
  return Matrix3d::Identity() + 0.5 * k + c * k * k;
}

[[noreturn]] void fail(const std::string& location, const std::string& detail) {
  throw InputError("pose graph", location, detail);
}

void checkPose(const Isometry3d& pose, const std::string& location) {
  if (!pose.matrix().allFinite()) fail(location, "non-finite pose");
  const Matrix3d r = pose.linear();
  if ((r.transpose() * r - Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 || r.determinant() < 0.0)
    fail(location, "the rotation part is not a rotation matrix (orthonormal, determinant +1)");
}

struct Kernel {
  RobustKernel type;
  double width2;
  // rho(s) for the squared Mahalanobis distance s, and its derivative
  // (the IRLS weight).
  double cost(double s) const {
    switch (type) {
      case RobustKernel::Huber:
        return s <= width2 ? s : 2.0 * std::sqrt(s * width2) - width2;
      case RobustKernel::Cauchy:
        return width2 * std::log1p(s / width2);
      case RobustKernel::None:
        break;
    }
    return s;
  }
  double weight(double s) const {
    switch (type) {
      case RobustKernel::Huber:
        return s <= width2 ? 1.0 : std::sqrt(width2 / s);
      case RobustKernel::Cauchy:
        return 1.0 / (1.0 + s / width2);
      case RobustKernel::None:
        break;
    }
    return 1.0;
  }
};

void validate(const PoseGraph& graph, const PoseGraphParameters& params) {
  const std::size_t n = graph.poses.size();
  for (std::size_t k = 0; k < n; ++k) checkPose(graph.poses[k], "node " + std::to_string(k));
  for (std::size_t e = 0; e < graph.edges.size(); ++e) {
    const PoseGraphEdge& edge = graph.edges[e];
    const std::string where = "edge " + std::to_string(e);
    if (edge.from >= n || edge.to >= n)
      fail(where, "refers to node " + std::to_string(std::max(edge.from, edge.to)) + ", the graph has " +
                      std::to_string(n) + " nodes");
    if (edge.from == edge.to) fail(where, "connects node " + std::to_string(edge.from) + " to itself");
    checkPose(edge.measurement, where);
    const Matrix6d& info = edge.information;
    if (!info.allFinite()) fail(where, "non-finite information matrix");
    if ((info - info.transpose()).cwiseAbs().maxCoeff() > 1e-9 * info.cwiseAbs().maxCoeff())
      fail(where, "the information matrix is not symmetric");
    Eigen::LLT<Matrix6d> llt(info);
    if (llt.info() != Eigen::Success) fail(where, "the information matrix is not positive definite");
  }
  if (graph.fixed.empty())
    fail("", "no fixed node: at least one pose must be held (a pose graph only fixes relative poses)");
  for (std::size_t f : graph.fixed)
    if (f >= n) fail("fixed node " + std::to_string(f), "out of range, the graph has " + std::to_string(n) + " nodes");

  // Every free node must be tied to a fixed one, or its pose is undetermined
  // and the normal equations singular.
  std::vector<std::vector<std::size_t>> adjacent(n);
  for (const PoseGraphEdge& edge : graph.edges) {
    adjacent[edge.from].push_back(edge.to);
    adjacent[edge.to].push_back(edge.from);
  }
  std::vector<char> reached(n, 0);
  std::deque<std::size_t> queue;
  for (std::size_t f : graph.fixed)
    if (!reached[f]) reached[f] = 1, queue.push_back(f);
  while (!queue.empty()) {
    const std::size_t k = queue.front();
    queue.pop_front();
    for (std::size_t m : adjacent[k])
      if (!reached[m]) reached[m] = 1, queue.push_back(m);
  }
  for (std::size_t k = 0; k < n; ++k)
    if (!reached[k]) fail("node " + std::to_string(k), "not connected to any fixed node through edges");

  if (params.max_iterations < 0) fail("max_iterations", "must be >= 0");
  if (!(params.initial_lambda >= 0.0) || !std::isfinite(params.initial_lambda))
    fail("initial_lambda", "must be finite and >= 0");
  if (!(params.update_tolerance >= 0.0)) fail("update_tolerance", "must be >= 0");
  if (!(params.relative_decrease_tolerance >= 0.0)) fail("relative_decrease_tolerance", "must be >= 0");
  if (params.kernel != RobustKernel::None && !(params.kernel_width > 0.0 && std::isfinite(params.kernel_width)))
    fail("kernel_width", "must be finite and > 0");
}

// The normal equations over the free nodes: H (upper triangle, block
// pattern fixed by the edges) and the gradient g = sum J^T W e.
class NormalEquations {
 public:
  NormalEquations(const PoseGraph& graph, const std::vector<std::size_t>& free_index, std::size_t free_count)
      : graph_(graph), free_index_(free_index), dim_(static_cast<int>(6 * free_count)) {
    // Block rows above the diagonal in each block column, sorted.
    std::vector<std::vector<std::size_t>> above(free_count);
    for (const PoseGraphEdge& edge : graph.edges) {
      const std::size_t a = free_index[edge.from], b = free_index[edge.to];
      if (a == kNotFree || b == kNotFree) continue;
      above[std::max(a, b)].push_back(std::min(a, b));
    }
    for (auto& rows : above) {
      std::sort(rows.begin(), rows.end());
      rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    }
    column_start_.assign(static_cast<std::size_t>(dim_) + 1, 0);
    std::vector<int> row_index;
    for (std::size_t q = 0; q < free_count; ++q) {
      for (int c = 0; c < 6; ++c) {
        for (std::size_t p : above[q])
          for (int r = 0; r < 6; ++r) row_index.push_back(static_cast<int>(6 * p) + r);
        for (int r = 0; r <= c; ++r) row_index.push_back(static_cast<int>(6 * q) + r);
        column_start_[6 * q + c + 1] = static_cast<int>(row_index.size());
      }
    }
    above_count_.resize(free_count);
    for (std::size_t q = 0; q < free_count; ++q) above_count_[q] = above[q].size();
    edge_slot_.assign(graph.edges.size(), 0);
    for (std::size_t e = 0; e < graph.edges.size(); ++e) {
      const std::size_t a = free_index[graph.edges[e].from], b = free_index[graph.edges[e].to];
      if (a == kNotFree || b == kNotFree) continue;
      const auto& rows = above[std::max(a, b)];
      edge_slot_[e] =
          static_cast<std::size_t>(std::lower_bound(rows.begin(), rows.end(), std::min(a, b)) - rows.begin());
    }
    solver_.analyse(dim_, column_start_, row_index);
    diagonal_.resize(static_cast<std::size_t>(dim_));
    gradient_.resize(static_cast<std::size_t>(dim_));
  }

  std::size_t nonzeros() const { return solver_.nonzeros(); }
  bool supernodal() const { return solver_.supernodal(); }
  double factorNonzeros() const { return solver_.factorNonzeros(); }

  void linearise(const std::vector<Isometry3d>& poses, const Kernel& kernel, std::vector<double>& weights) {
    double* h = solver_.values();
    std::fill_n(h, column_start_.back(), 0.0);
    std::fill(gradient_.begin(), gradient_.end(), 0.0);
    for (std::size_t e = 0; e < graph_.edges.size(); ++e) {
      const PoseGraphEdge& edge = graph_.edges[e];
      const std::size_t a = free_index_[edge.from], b = free_index_[edge.to];
      if (a == kNotFree && b == kNotFree) continue;
      Matrix6d ja, jb;
      const Vector6d err = poseGraphEdgeError(poses[edge.from], poses[edge.to], edge.measurement, &ja, &jb);
      const Matrix6d info = 0.5 * (edge.information + edge.information.transpose());
      const double s = err.dot(info * err);
      const double w = edge.robust ? kernel.weight(s) : 1.0;
      weights[e] = w;
      const Matrix6d wi = w * info;
      if (a != kNotFree) {
        addDiagonal(h, a, ja.transpose() * wi * ja);
        Eigen::Map<Vector6d>(gradient_.data() + 6 * a) += ja.transpose() * wi * err;
      }
      if (b != kNotFree) {
        addDiagonal(h, b, jb.transpose() * wi * jb);
        Eigen::Map<Vector6d>(gradient_.data() + 6 * b) += jb.transpose() * wi * err;
      }
      if (a != kNotFree && b != kNotFree) {
        const Matrix6d hab = ja.transpose() * wi * jb;
        // Stored block (min, max): rows of the lower-numbered node.
        const std::size_t q = std::max(a, b);
        const Matrix6d block = a < b ? hab : Matrix6d(hab.transpose());
        for (int c = 0; c < 6; ++c) {
          double* column = h + column_start_[6 * q + c] + 6 * edge_slot_[e];
          for (int r = 0; r < 6; ++r) column[r] += block(r, c);
        }
      }
    }
    for (int d = 0; d < dim_; ++d) diagonal_[static_cast<std::size_t>(d)] = h[column_start_[d + 1] - 1];
  }

  // The cost decrease the quadratic model predicts for a step solved with
  // `lambda`: with cost sum e^T W e, gradient 2 g and (H + lambda D) delta
  // = -g, it is -g.delta + lambda delta^T D delta.
  double predictedDecrease(double lambda, const std::vector<double>& delta) const {
    double decrease = 0.0;
    for (std::size_t d = 0; d < delta.size(); ++d)
      decrease += -gradient_[d] * delta[d] + lambda * diagonal_[d] * delta[d] * delta[d];
    return decrease;
  }

  // Solves (H + lambda diag(H)) delta = -g; false when not positive definite.
  bool solve(double lambda, std::vector<double>& delta) {
    double* h = solver_.values();
    for (int d = 0; d < dim_; ++d)
      h[column_start_[d + 1] - 1] = diagonal_[static_cast<std::size_t>(d)] * (1.0 + lambda);
    if (!solver_.factorise()) return false;
    solver_.solve(gradient_, delta);
    for (double& x : delta) x = -x;
    return true;
  }

 private:
  void addDiagonal(double* h, std::size_t q, const Matrix6d& block) {
    for (int c = 0; c < 6; ++c) {
      double* column = h + column_start_[6 * q + c] + 6 * above_count_[q];
      for (int r = 0; r <= c; ++r) column[r] += block(r, c);
    }
  }

  const PoseGraph& graph_;
  const std::vector<std::size_t>& free_index_;
  int dim_;
  std::vector<int> column_start_;
  std::vector<std::size_t> above_count_;
  std::vector<std::size_t> edge_slot_;
  std::vector<double> diagonal_;
  std::vector<double> gradient_;
  CholmodSolver solver_;
};

struct Cost {
  double chi2 = 0.0;
  double robust = 0.0;
};

Cost evaluate(const PoseGraph& graph, const std::vector<Isometry3d>& poses, const Kernel& kernel) {
  Cost cost;
  for (const PoseGraphEdge& edge : graph.edges) {
    const Vector6d err = poseGraphEdgeError(poses[edge.from], poses[edge.to], edge.measurement);
    const double s = err.dot(0.5 * (edge.information + edge.information.transpose()) * err);
    cost.chi2 += s;
    cost.robust += edge.robust ? kernel.cost(s) : s;
  }
  return cost;
}

}  // namespace

Matrix6d poseGraphInformation(double sigma_translation, double sigma_rotation) {
  if (!(sigma_translation > 0.0) || !std::isfinite(sigma_translation))
    throw InputError("sigma_translation", "", "must be finite and > 0");
  if (!(sigma_rotation > 0.0) || !std::isfinite(sigma_rotation))
    throw InputError("sigma_rotation", "", "must be finite and > 0");
  Vector6d d;
  d.head<3>().setConstant(1.0 / (sigma_translation * sigma_translation));
  d.tail<3>().setConstant(1.0 / (sigma_rotation * sigma_rotation));
  return d.asDiagonal();
}

Isometry3d poseGraphRetract(const Isometry3d& pose, const Vector6d& delta) {
  Isometry3d out = Isometry3d::Identity();
  out.translation() = pose.translation() + pose.linear() * delta.head<3>();
  // Re-orthonormalised so that thousands of updates do not let the
  // rotation drift away from SO(3).
  out.linear() = Quaterniond(pose.linear() * expSO3(delta.tail<3>())).normalized().toRotationMatrix();
  return out;
}

Vector6d poseGraphEdgeError(const Isometry3d& pose_i, const Isometry3d& pose_j, const Isometry3d& measurement,
                            Matrix6d* jacobian_i, Matrix6d* jacobian_j) {
  const Isometry3d e = measurement.inverse(Eigen::Isometry) * pose_i.inverse(Eigen::Isometry) * pose_j;
  Vector6d err;
  err.head<3>() = e.translation();
  err.tail<3>() = logSO3(e.linear());
  if (!jacobian_i && !jacobian_j) return err;
  const Matrix3d jr_inv = rightJacobianInverse(err.tail<3>());
  const Matrix3d re = e.linear();
  if (jacobian_j) {
    // E (+) delta_j: E [Exp(theta), rho].
    jacobian_j->setZero();
    jacobian_j->topLeftCorner<3, 3>() = re;
    jacobian_j->bottomRightCorner<3, 3>() = jr_inv;
  }
  if (jacobian_i) {
    // T_i (+) delta_i enters inverted and on the far side of T_ij: the
    // perturbation is carried through T_ij^-1 (adjoint) before it acts on E.
    const Matrix3d rz_t = measurement.linear().transpose();
    jacobian_i->setZero();
    jacobian_i->topLeftCorner<3, 3>() = -rz_t;
    jacobian_i->topRightCorner<3, 3>() = skew(e.translation()) * rz_t + rz_t * skew(measurement.translation());
    jacobian_i->bottomRightCorner<3, 3>() = -jr_inv * re.transpose() * rz_t;
  }
  return err;
}

PoseGraphResult optimisePoseGraph(const PoseGraph& graph, const PoseGraphParameters& params) {
  const auto start = std::chrono::steady_clock::now();
  validate(graph, params);
  const std::size_t n = graph.poses.size();
  const Kernel kernel{params.kernel, params.kernel_width * params.kernel_width};

  PoseGraphResult result;
  result.poses = graph.poses;
  PoseGraphReport& report = result.report;
  report.edge_weights.assign(graph.edges.size(), 1.0);

  std::vector<std::size_t> free_index(n, 0);
  for (std::size_t f : graph.fixed) free_index[f] = kNotFree;
  std::size_t free_count = 0;
  for (std::size_t k = 0; k < n; ++k)
    if (free_index[k] != kNotFree) free_index[k] = free_count++;
  report.free_nodes = free_count;

  Cost cost = evaluate(graph, result.poses, kernel);
  report.initial_chi2 = cost.chi2;
  report.initial_cost = cost.robust;

  if (free_count > 0) {
    NormalEquations normal(graph, free_index, free_count);
    report.nonzeros = normal.nonzeros();
    report.factor_nonzeros = static_cast<std::size_t>(normal.factorNonzeros());
    std::vector<double> delta;
    std::vector<Isometry3d> candidate(n);
    // One Levenberg-Marquardt (or Gauss-Newton) run with a given kernel,
    // with its own iteration budget; true when a tolerance was met. A budget
    // shared by the warm start and every annealing stage ran out before the
    // final kernel on graphs with wrong pairs (a bottle's: the result then
    // depended on the last bits of the starting poses).
    auto run = [&](const Kernel& stage_kernel) {
      Cost stage_cost = evaluate(graph, result.poses, stage_kernel);
      double lambda = params.levenberg_marquardt ? params.initial_lambda : 0.0;
      double lambda_growth = 2.0;
      bool relinearise = true;
      bool converged = false;
      for (int iteration = 0; iteration < params.max_iterations; ++iteration) {
        ++report.iterations;
        if (relinearise) normal.linearise(result.poses, stage_kernel, report.edge_weights);
        relinearise = false;
        if (!normal.solve(lambda, delta)) {
          // Only rounding can make H indefinite (validation guarantees a
          // connected, positive definite problem): damp harder.
          lambda = std::max(lambda * lambda_growth, 1e-9);
          lambda_growth *= 2.0;
          continue;
        }
        double step = 0.0;
        for (double x : delta) step = std::max(step, std::abs(x));
        candidate = result.poses;
        for (std::size_t k = 0; k < n; ++k)
          if (free_index[k] != kNotFree)
            candidate[k] =
                poseGraphRetract(result.poses[k], Eigen::Map<const Vector6d>(delta.data() + 6 * free_index[k]));
        const Cost next = evaluate(graph, candidate, stage_kernel);
        const bool accept = !params.levenberg_marquardt || next.robust < stage_cost.robust;
        if (accept) {
          const double decrease = stage_cost.robust - next.robust;
          if (params.levenberg_marquardt) {
            // Nielsen's rule: damp less the better the quadratic model
            // predicted the decrease.
            const double predicted = normal.predictedDecrease(lambda, delta);
            const double gain = predicted > 0.0 ? decrease / predicted : 1.0;
            lambda *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * gain - 1.0, 3));
            lambda_growth = 2.0;
          }
          result.poses.swap(candidate);
          stage_cost = next;
          ++report.accepted_steps;
          relinearise = true;
          if (step <= params.update_tolerance ||
              std::abs(decrease) <= params.relative_decrease_tolerance * stage_cost.robust ||
              stage_cost.robust == 0.0) {
            converged = true;
            break;
          }
        } else {
          // A step this small that still does not lower the cost means the
          // cost is at its floor of rounding.
          if (step <= params.update_tolerance) {
            converged = true;
            break;
          }
          lambda = std::max(lambda * lambda_growth, 1e-9);
          lambda_growth *= 2.0;
        }
      }
      return converged;
    };
    // From a drifted start a correct loop closure can look as wrong as a
    // false one (both hundreds of sigmas off); a robust kernel would then
    // discard both. Plain least squares first spreads the drift, after
    // which only the inconsistent edges stand out.
    if (kernel.type != RobustKernel::None && params.robust_warm_start) {
      run(Kernel{RobustKernel::None, 1.0});
      // Graduated non-convexity: a kernel as wide as the worst residual is
      // nearly quadratic; narrowing it step by step lets the inconsistent
      // edges let go one after another, the most inconsistent first, instead
      // of the least-squares compromise being locked in at once.
      if (params.kernel_annealing > 1.0) {
        double widest2 = kernel.width2;
        for (const PoseGraphEdge& edge : graph.edges) {
          if (!edge.robust) continue;
          const Vector6d err = poseGraphEdgeError(result.poses[edge.from], result.poses[edge.to], edge.measurement);
          widest2 = std::max(widest2, err.dot(0.5 * (edge.information + edge.information.transpose()) * err));
        }
        const double factor2 = params.kernel_annealing * params.kernel_annealing;
        for (double width2 = widest2 / factor2; width2 > kernel.width2; width2 /= factor2)
          run(Kernel{kernel.type, width2});
      }
    }
    report.converged = run(kernel);
    cost = evaluate(graph, result.poses, kernel);
    report.supernodal = normal.supernodal();
    // Weights as seen at the returned poses.
    for (std::size_t e = 0; e < graph.edges.size(); ++e) {
      const PoseGraphEdge& edge = graph.edges[e];
      const Vector6d err = poseGraphEdgeError(result.poses[edge.from], result.poses[edge.to], edge.measurement);
      const double s = err.dot(0.5 * (edge.information + edge.information.transpose()) * err);
      report.edge_weights[e] = edge.robust ? kernel.weight(s) : 1.0;
    }
  } else {
    report.converged = true;
  }
  report.final_chi2 = cost.chi2;
  report.final_cost = cost.robust;
  report.time_ms = millisecondsSince(start);
  return result;
}

}  // namespace icrkit::reconstruction
