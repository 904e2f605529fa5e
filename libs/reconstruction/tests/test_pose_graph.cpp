#include <icrkit/reconstruction/registration/pose_graph.hpp>

#include <icrkit/core/error.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>

namespace icrkit::reconstruction {
namespace {

using Eigen::AngleAxisd;
using Eigen::Isometry3d;
using Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

Isometry3d makePose(const Vector3d& rotation_vector, const Vector3d& translation) {
  Isometry3d t = Isometry3d::Identity();
  const double angle = rotation_vector.norm();
  if (angle > 0.0) t.linear() = AngleAxisd(angle, rotation_vector / angle).toRotationMatrix();
  t.translation() = translation;
  return t;
}

Isometry3d randomPose(std::mt19937& rng, double max_angle, double max_translation) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vector3d axis(u(rng), u(rng), u(rng));
  axis.normalize();
  return makePose(axis * (max_angle * std::abs(u(rng))), max_translation * Vector3d(u(rng), u(rng), u(rng)));
}

Isometry3d noisePose(std::mt19937& rng, double sigma_translation, double sigma_rotation) {
  std::normal_distribution<double> g(0.0, 1.0);
  const Vector3d r(g(rng), g(rng), g(rng));
  const Vector3d t(g(rng), g(rng), g(rng));
  return makePose(sigma_rotation * r, sigma_translation * t);
}

double rotationAngle(const Isometry3d& a, const Isometry3d& b) {
  return AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

struct Errors {
  double max_translation = 0.0;  // metres
  double max_rotation = 0.0;     // radians
  double rms_translation = 0.0;
};

Errors poseErrors(const std::vector<Isometry3d>& estimate, const std::vector<Isometry3d>& truth) {
  Errors e;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    const double dt = (estimate[k].translation() - truth[k].translation()).norm();
    e.max_translation = std::max(e.max_translation, dt);
    e.rms_translation += dt * dt;
    e.max_rotation = std::max(e.max_rotation, rotationAngle(estimate[k], truth[k]));
  }
  e.rms_translation = std::sqrt(e.rms_translation / static_cast<double>(truth.size()));
  return e;
}

// 36 scans on a circle of radius 0.6 m at 10 degree steps (a turntable
// sequence seen from the object), each looking at the axis.
std::vector<Isometry3d> turntableTruth() {
  std::vector<Isometry3d> poses;
  for (int k = 0; k < 36; ++k) {
    const double a = k * 10.0 * kDeg;
    Isometry3d t = Isometry3d::Identity();
    t.linear() = (AngleAxisd(a, Vector3d::UnitZ()) * AngleAxisd(-0.5 * kPi, Vector3d::UnitY()) *
                  AngleAxisd(0.3, Vector3d::UnitX()))
                     .toRotationMatrix();
    t.translation() = Vector3d(0.6 * std::cos(a), 0.6 * std::sin(a), 0.3);
    poses.push_back(t);
  }
  return poses;
}

// The turntable axis (world z) in the scans' own frame: the same for every
// scan, since they differ by rotations about it.
Vector3d axisInScan(const std::vector<Isometry3d>& truth) {
  return truth[0].linear().transpose() * Vector3d::UnitZ();
}

// Odometry k -> k+1 with a systematic drift `drift` (applied in the scan
// frame) and Gaussian noise (1 mm, 0.1 deg per axis); one loop closure
// 35 -> 0 with 0.5 mm / 0.05 deg noise. The initial guess chains the
// odometry from the true first pose.
PoseGraph drifingChain(const std::vector<Isometry3d>& truth, const Isometry3d& drift, std::uint32_t seed) {
  std::mt19937 rng(seed);
  PoseGraph graph;
  graph.poses.push_back(truth[0]);
  for (std::size_t k = 0; k + 1 < truth.size(); ++k) {
    PoseGraphEdge edge;
    edge.from = k;
    edge.to = k + 1;
    edge.measurement = truth[k].inverse() * truth[k + 1] * drift * noisePose(rng, 0.001, 0.1 * kDeg);
    edge.information = poseGraphInformation(0.002, 0.3 * kDeg);
    graph.edges.push_back(edge);
    graph.poses.push_back(graph.poses.back() * edge.measurement);
  }
  PoseGraphEdge loop;
  loop.from = truth.size() - 1;
  loop.to = 0;
  loop.measurement = truth.back().inverse() * truth[0] * noisePose(rng, 0.0005, 0.05 * kDeg);
  loop.information = poseGraphInformation(0.001, 0.1 * kDeg);
  graph.edges.push_back(loop);
  return graph;
}

// The drift a turntable sequence typically shows: each registration
// over-rotates by 0.3 deg about the turntable axis and climbs 0.5 mm along it.
// Both add up around the loop, so the loop closure sees all of it.
PoseGraph turntableChain(const std::vector<Isometry3d>& truth, std::uint32_t seed) {
  const Vector3d axis = axisInScan(truth);
  return drifingChain(truth, makePose(0.3 * kDeg * axis, 0.0005 * axis), seed);
}

TEST(PoseGraph, AnalyticJacobiansMatchNumericDifferences) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    const Isometry3d ti = randomPose(rng, 3.0, 2.0), tj = randomPose(rng, 3.0, 2.0);
    // Small errors (near convergence) and large ones (a poor start).
    const double error_angle = trial % 2 == 0 ? 0.05 : 2.0;
    Isometry3d z = ti.inverse() * tj * randomPose(rng, error_angle, 0.3);
    // And errors close to half a turn, where Jr^-1 is largest.
    if (trial % 5 == 4)
      z = ti.inverse() * tj * makePose(3.1 * randomPose(rng, 1.0, 0.0).linear().col(0), Vector3d(0.1, 0.2, 0.3));
    Matrix6d ji, jj;
    poseGraphEdgeError(ti, tj, z, &ji, &jj);
    const double h = 1e-6;
    Matrix6d ni, nj;
    for (int c = 0; c < 6; ++c) {
      Vector6d d = Vector6d::Zero();
      d[c] = h;
      ni.col(c) =
          (poseGraphEdgeError(poseGraphRetract(ti, d), tj, z) - poseGraphEdgeError(poseGraphRetract(ti, -d), tj, z)) /
          (2 * h);
      nj.col(c) =
          (poseGraphEdgeError(ti, poseGraphRetract(tj, d), z) - poseGraphEdgeError(ti, poseGraphRetract(tj, -d), z)) /
          (2 * h);
    }
    EXPECT_LT((ji - ni).cwiseAbs().maxCoeff(), 1e-7) << "trial " << trial << "\n" << ji << "\n\n" << ni;
    EXPECT_LT((jj - nj).cwiseAbs().maxCoeff(), 1e-7) << "trial " << trial << "\n" << jj << "\n\n" << nj;
  }
}

TEST(PoseGraph, ErrorIsZeroForAConsistentMeasurementAndRetractIsExp) {
  std::mt19937 rng(3);
  const Isometry3d ti = randomPose(rng, 2.0, 1.0), tj = randomPose(rng, 2.0, 1.0);
  EXPECT_LT(poseGraphEdgeError(ti, tj, ti.inverse() * tj).norm(), 1e-12);
  Vector6d d;
  d << 0.1, -0.2, 0.3, 0.0, 0.0, 0.5;
  const Isometry3d moved = poseGraphRetract(ti, d);
  EXPECT_LT((moved.translation() - (ti.translation() + ti.linear() * d.head<3>())).norm(), 1e-14);
  EXPECT_NEAR(rotationAngle(ti, moved), 0.5, 1e-12);
}

TEST(PoseGraph, TinyConsistentGraphIsSolvedExactly) {
  std::mt19937 rng(11);
  std::vector<Isometry3d> truth = {randomPose(rng, 1.0, 1.0), randomPose(rng, 1.0, 1.0), randomPose(rng, 1.0, 1.0),
                                   randomPose(rng, 1.0, 1.0)};
  PoseGraph graph;
  const std::pair<std::size_t, std::size_t> pairs[] = {{0, 1}, {1, 2}, {2, 3}, {0, 2}, {3, 1}};
  for (auto [i, j] : pairs) {
    PoseGraphEdge e;
    e.from = i;
    e.to = j;
    e.measurement = truth[i].inverse() * truth[j];
    e.information = poseGraphInformation(0.01, 0.02);
    graph.edges.push_back(e);
  }
  graph.poses = truth;
  for (std::size_t k = 1; k < truth.size(); ++k) graph.poses[k] = truth[k] * randomPose(rng, 0.3, 0.2);
  for (bool lm : {true, false}) {
    PoseGraphParameters params;
    params.levenberg_marquardt = lm;
    const PoseGraphResult result = optimisePoseGraph(graph, params);
    const Errors err = poseErrors(result.poses, truth);
    EXPECT_LT(err.max_translation, 1e-10) << "LM " << lm;
    EXPECT_LT(err.max_rotation, 1e-10) << "LM " << lm;
    EXPECT_LT(result.report.final_chi2, 1e-16);
    EXPECT_GT(result.report.initial_chi2, 100.0);
    EXPECT_TRUE(result.report.converged);
    EXPECT_LE(result.report.iterations, 20);
    EXPECT_EQ(result.report.free_nodes, 3u);
    EXPECT_TRUE(result.poses[0].isApprox(truth[0], 0.0));
  }
}

TEST(PoseGraph, SingleEdgePlacesTheFreeNode) {
  std::mt19937 rng(5);
  PoseGraph graph;
  graph.poses = {randomPose(rng, 2.0, 1.0), Isometry3d::Identity()};
  PoseGraphEdge e;
  e.from = 1;  // edge stored "backwards": node 1 free, node 0 fixed
  e.to = 0;
  e.measurement = randomPose(rng, 2.5, 1.0);
  graph.edges.push_back(e);
  const PoseGraphResult result = optimisePoseGraph(graph);
  const Isometry3d expected = graph.poses[0] * e.measurement.inverse();
  EXPECT_LT((result.poses[1].matrix() - expected.matrix()).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(PoseGraph, DriftingTurntableChainRecoversTheTruth) {
  const std::vector<Isometry3d> truth = turntableTruth();
  const PoseGraph graph = turntableChain(truth, 42);
  const Errors before = poseErrors(graph.poses, truth);
  const PoseGraphResult result = optimisePoseGraph(graph);
  const Errors after = poseErrors(result.poses, truth);
  // The same noise without the drift: what the single loop closure can give
  // at best. The drift should be gone, leaving the noise's random walk.
  const PoseGraph undrifted = drifingChain(truth, Isometry3d::Identity(), 42);
  const PoseGraphResult reference = optimisePoseGraph(undrifted);
  const Errors noise_only = poseErrors(reference.poses, truth);
  const Errors versus_reference = poseErrors(result.poses, reference.poses);
  std::cout << "turntable chain without drift: max " << noise_only.max_translation * 1e3 << " mm / "
            << noise_only.max_rotation / kDeg << " deg; drifting vs undrifted solution: max "
            << versus_reference.max_translation * 1e3 << " mm / " << versus_reference.max_rotation / kDeg << " deg\n";
  std::cout << "turntable chain: before max " << before.max_translation * 1e3 << " mm / " << before.max_rotation / kDeg
            << " deg (rms " << before.rms_translation * 1e3 << " mm); after max " << after.max_translation * 1e3
            << " mm / " << after.max_rotation / kDeg << " deg (rms " << after.rms_translation * 1e3 << " mm); chi2 "
            << result.report.initial_chi2 << " -> " << result.report.final_chi2 << " in " << result.report.iterations
            << " iterations, " << result.report.time_ms << " ms\n";
  EXPECT_GT(before.max_translation, 0.05);
  EXPECT_LT(after.max_translation, 0.015);
  EXPECT_LT(after.max_rotation, 1.2 * kDeg);
  EXPECT_LT(versus_reference.max_translation, 0.003);
  EXPECT_LT(versus_reference.max_rotation, 0.5 * kDeg);
  EXPECT_TRUE(result.report.converged);
  // The noise alone gives chi2 ~ 38 here (1 mm against sigma 2 mm, 0.1 deg
  // against 0.3 deg, 35 edges), minus what the 35 free poses absorb.
  EXPECT_LT(result.report.final_chi2, 300.0);
}

TEST(PoseGraph, DriftThatCancelsAroundTheLoopIsNotObservable) {
  // A tilt of 0.1 deg and a 1 mm sideways step per scan, fixed in the scan
  // frame, precess with the turntable: their sum over the full turn nearly
  // cancels, so the single loop closure cannot see the error midway. The
  // optimiser reaches the least-squares optimum (chi2 near its 6 degrees of
  // freedom) but the poses keep most of the drift.
  const std::vector<Isometry3d> truth = turntableTruth();
  const PoseGraph graph =
      drifingChain(truth, makePose(Vector3d(0.1 * kDeg, 0.0, 0.3 * kDeg), Vector3d(0.0, 0.001, 0.0)), 42);
  const Errors before = poseErrors(graph.poses, truth);
  const PoseGraphResult result = optimisePoseGraph(graph);
  const Errors after = poseErrors(result.poses, truth);
  std::cout << "precessing drift: before max " << before.max_translation * 1e3 << " mm / " << before.max_rotation / kDeg
            << " deg; after max " << after.max_translation * 1e3 << " mm / " << after.max_rotation / kDeg
            << " deg; chi2 " << result.report.initial_chi2 << " -> " << result.report.final_chi2 << "\n";
  EXPECT_TRUE(result.report.converged);
  EXPECT_LT(result.report.final_chi2, 20.0);
  EXPECT_LT(after.max_translation, before.max_translation);
}

// Consecutive registrations are trusted; only loop closures may be wrong:
// one more, 45 deg and 20 cm off, between scans 9 and 27, as precise as a
// good registration claims to be (the last edge).
void addWrongLoopClosure(PoseGraph& graph, const std::vector<Isometry3d>& truth) {
  for (std::size_t e = 0; e + 1 < graph.edges.size(); ++e) graph.edges[e].robust = false;
  PoseGraphEdge wrong;
  wrong.from = 9;
  wrong.to = 27;
  wrong.measurement =
      truth[9].inverse() * truth[27] * makePose(Vector3d(0.0, 45.0 * kDeg, 0.0), Vector3d(0.2, 0.0, 0.0));
  wrong.information = poseGraphInformation(0.001, 0.1 * kDeg);
  graph.edges.push_back(wrong);
}

TEST(PoseGraph, CauchyKernelRejectsAWrongLoopClosure) {
  const std::vector<Isometry3d> truth = turntableTruth();
  PoseGraph graph = turntableChain(truth, 42);
  const Errors clean = poseErrors(optimisePoseGraph(graph).poses, truth);
  addWrongLoopClosure(graph, truth);

  const Errors plain = poseErrors(optimisePoseGraph(graph).poses, truth);
  PoseGraphParameters params;
  params.kernel = RobustKernel::Cauchy;
  const PoseGraphResult robust = optimisePoseGraph(graph, params);
  std::cout << "Cauchy: " << robust.report.iterations << " iterations, weights of the loop closures "
            << robust.report.edge_weights[35] << " (correct), " << robust.report.edge_weights[36] << " (wrong)\n";
  const Errors cauchy = poseErrors(robust.poses, truth);
  PoseGraphParameters at_once = params;
  at_once.kernel_annealing = 1.0;
  const Errors cauchy_at_once = poseErrors(optimisePoseGraph(graph, at_once).poses, truth);
  at_once.robust_warm_start = false;
  const Errors cauchy_cold = poseErrors(optimisePoseGraph(graph, at_once).poses, truth);
  std::cout << "Cauchy without annealing: " << cauchy_at_once.max_translation * 1e3
            << " mm, without warm start either: " << cauchy_cold.max_translation * 1e3 << " mm\n";
  params.kernel = RobustKernel::Huber;
  const Errors huber = poseErrors(optimisePoseGraph(graph, params).poses, truth);
  std::cout << "wrong loop closure: max error clean " << clean.max_translation * 1e3 << " mm, plain "
            << plain.max_translation * 1e3 << " mm, Huber " << huber.max_translation * 1e3 << " mm, Cauchy "
            << cauchy.max_translation * 1e3 << " mm; Cauchy weight of the wrong edge "
            << robust.report.edge_weights.back() << "\n";
  EXPECT_GT(plain.max_translation, 0.02);
  EXPECT_LT(cauchy.max_translation, clean.max_translation + 0.002);
  EXPECT_LT(robust.report.edge_weights.back(), 0.01);
}

TEST(PoseGraph, EveryAnnealingStageGetsItsOwnIterationBudget) {
  // The wrong loop closure above makes the kernel anneal over several
  // stages. With a budget shared by the warm start and all stages, a small
  // one ran out before the final kernel: the wrong edge kept weight and the
  // poses depended on where the budget ended. Each stage now has its own.
  const std::vector<Isometry3d> truth = turntableTruth();
  PoseGraph graph = turntableChain(truth, 42);
  const Errors clean = poseErrors(optimisePoseGraph(graph).poses, truth);
  addWrongLoopClosure(graph, truth);
  PoseGraphParameters params;
  params.kernel = RobustKernel::Cauchy;
  params.max_iterations = 6;
  const PoseGraphResult robust = optimisePoseGraph(graph, params);
  EXPECT_GT(robust.report.iterations, params.max_iterations);  // several stages ran
  EXPECT_LT(robust.report.edge_weights.back(), 0.01);
  EXPECT_LT(poseErrors(robust.poses, truth).max_translation, clean.max_translation + 0.002);
}

TEST(PoseGraph, IsDeterministic) {
  const std::vector<Isometry3d> truth = turntableTruth();
  const PoseGraph graph = turntableChain(truth, 9);
  PoseGraphParameters params;
  params.kernel = RobustKernel::Huber;
  const PoseGraphResult a = optimisePoseGraph(graph, params);
  const PoseGraphResult b = optimisePoseGraph(graph, params);
  ASSERT_EQ(a.poses.size(), b.poses.size());
  for (std::size_t k = 0; k < a.poses.size(); ++k) EXPECT_TRUE(a.poses[k].matrix() == b.poses[k].matrix()) << k;
  EXPECT_EQ(a.report.iterations, b.report.iterations);
  EXPECT_EQ(a.report.final_chi2, b.report.final_chi2);
}

TEST(PoseGraph, LargerGraphSpeed) {
  // Random walks with a loop closure to the node 50 back every 25 nodes:
  // sparse, long-chain problems like a multi-sequence scan set.
  for (const std::size_t n : {std::size_t{2000}, std::size_t{10000}}) {
    std::mt19937 rng(1);
    std::vector<Isometry3d> truth = {Isometry3d::Identity()};
    for (std::size_t k = 1; k < n; ++k) truth.push_back(truth.back() * randomPose(rng, 0.2, 0.1));
    PoseGraph graph;
    graph.poses.push_back(truth[0]);
    auto add = [&](std::size_t i, std::size_t j) {
      PoseGraphEdge e;
      e.from = i;
      e.to = j;
      e.measurement = truth[i].inverse() * truth[j] * noisePose(rng, 0.002, 0.2 * kDeg);
      e.information = poseGraphInformation(0.002, 0.2 * kDeg);
      graph.edges.push_back(e);
    };
    for (std::size_t k = 0; k + 1 < n; ++k) {
      add(k, k + 1);
      graph.poses.push_back(graph.poses.back() * graph.edges.back().measurement);
    }
    for (std::size_t k = 50; k < n; k += 25) add(k, k - 50);
    const PoseGraphResult result = optimisePoseGraph(graph);
    const Errors before = poseErrors(graph.poses, truth), after = poseErrors(result.poses, truth);
    std::cout << n << " nodes, " << graph.edges.size() << " edges: " << result.report.iterations << " iterations ("
              << result.report.accepted_steps << " accepted), " << result.report.time_ms << " ms, nnz(H upper) "
              << result.report.nonzeros << ", nnz(L) " << result.report.factor_nonzeros
              << (result.report.supernodal ? " supernodal" : " simplicial") << ", chi2 " << result.report.initial_chi2
              << " -> " << result.report.final_chi2 << ", max error " << before.max_translation << " -> "
              << after.max_translation << " m\n";
    EXPECT_TRUE(result.report.converged);
    EXPECT_LT(after.max_translation, before.max_translation);
    // Near the chi2 expectation: 6 x (edges - free nodes) = 6 x (n / 25 - 1).
    const double dof = 6.0 * static_cast<double>(graph.edges.size() - (n - 1));
    EXPECT_LT(result.report.final_chi2, 1.5 * dof);
  }
}

PoseGraph smallGraph() {
  PoseGraph graph;
  graph.poses.assign(3, Isometry3d::Identity());
  for (std::size_t k = 0; k < 2; ++k) {
    PoseGraphEdge e;
    e.from = k;
    e.to = k + 1;
    graph.edges.push_back(e);
  }
  return graph;
}

TEST(PoseGraph, BadInputThrowsInputError) {
  EXPECT_NO_THROW(optimisePoseGraph(smallGraph()));
  {
    PoseGraph g = smallGraph();
    g.edges[1].to = 5;
    EXPECT_THROW(optimisePoseGraph(g), InputError);
  }
  {
    PoseGraph g = smallGraph();
    g.edges[0].to = 0;
    EXPECT_THROW(optimisePoseGraph(g), InputError);
  }
  {
    PoseGraph g = smallGraph();
    g.edges[0].information.bottomRightCorner<3, 3>().setZero();  // semi-definite
    EXPECT_THROW(optimisePoseGraph(g), InputError);
  }
  {
    PoseGraph g = smallGraph();
    g.edges[0].information(0, 0) = -1.0;
    EXPECT_THROW(optimisePoseGraph(g), InputError);
  }
  {
    PoseGraph g = smallGraph();
    g.edges[0].information(0, 1) = 0.5;  // not symmetric
    EXPECT_THROW(optimisePoseGraph(g), InputError);
  }
  {
    PoseGraph g = smallGraph();
    g.fixed.clear();
    EXPECT_THROW(optimisePoseGraph(g), InputError);
  }
  {
    PoseGraph g = smallGraph();
    g.fixed = {3};
    EXPECT_THROW(optimisePoseGraph(g), InputError);
  }
  {
    PoseGraph g = smallGraph();
    g.poses.push_back(Isometry3d::Identity());  // node 3: no edge
    EXPECT_THROW(optimisePoseGraph(g), InputError);
  }
  {
    PoseGraph g = smallGraph();
    g.poses[1].linear()(0, 0) = 2.0;
    EXPECT_THROW(optimisePoseGraph(g), InputError);
  }
  {
    PoseGraph g = smallGraph();
    g.edges[0].measurement.translation().x() = std::nan("");
    EXPECT_THROW(optimisePoseGraph(g), InputError);
  }
  {
    PoseGraphParameters p;
    p.kernel = RobustKernel::Cauchy;
    p.kernel_width = 0.0;
    EXPECT_THROW(optimisePoseGraph(smallGraph(), p), InputError);
  }
  EXPECT_THROW(poseGraphInformation(0.0, 1.0), InputError);
}

TEST(PoseGraph, AllNodesFixedOnlyEvaluates) {
  PoseGraph g = smallGraph();
  g.fixed = {0, 1, 2};
  g.edges[0].measurement.translation().x() = 1.0;
  const PoseGraphResult r = optimisePoseGraph(g);
  EXPECT_EQ(r.report.free_nodes, 0u);
  EXPECT_DOUBLE_EQ(r.report.final_chi2, 1.0);
  EXPECT_EQ(r.report.iterations, 0);
}

}  // namespace
}  // namespace icrkit::reconstruction
