#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/icr/grasp_sampling.hpp>
#include <icrkit/icr/independent_contact_regions.hpp>

#include <gtest/gtest.h>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <icrkit/core/mesh_primitives.hpp>

#include <map>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace icrkit::icr {
namespace {

// A geodesic sphere of radius r (metres) with exact outward normals:
// 10 * 4^levels + 2 vertices.
TriangleMesh geodesicSphere(int levels, double r) { return makeIcosphere(levels, r); }

ContactModel frictional(double mu = 0.8, int edges = 8) {
  ContactModel model;
  model.type = ContactType::Frictional;
  model.friction = mu;
  model.cone_edges = edges;
  return model;
}

// The wrenches of contacts at unit directions u_i on a sphere of radius r
// centred on the torque reference.
WrenchSet sphereWrenches(const std::vector<Eigen::Vector3d>& directions, const ContactModel& model, double r = 0.05) {
  WrenchFrame frame;
  frame.lambda = r;
  const ContactWrenches contact(model, frame);
  WrenchSet w(6, static_cast<Eigen::Index>(directions.size() * contact.perContact()));
  for (std::size_t i = 0; i < directions.size(); ++i) {
    const Eigen::Vector3d n = directions[i].normalized();
    contact.compute(r * n, n, w, static_cast<Eigen::Index>(i * contact.perContact()));
  }
  return w;
}

std::vector<Eigen::Vector3d> tetrahedron() {
  return {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
}

// ---------------------------------------------------------------------------
// mayBeForceClosure on sets with known answers.

TEST(MayBeForceClosure, TetrahedralSphereGraspIsForceClosure) {
  const WrenchSet w = sphereWrenches(tetrahedron(), frictional());
  ASSERT_TRUE(computeGraspWrenchSpace(w).force_closure);
  EXPECT_TRUE(mayBeForceClosure(w));
}

TEST(MayBeForceClosure, FourContactsOnOneSideAreRejected) {
  // Normals within 30 degrees of +z and a cone half-angle of atan(0.8) = 39
  // degrees: every force has a positive z component.
  const std::vector<Eigen::Vector3d> cap = {{0.3, 0, 1}, {-0.3, 0, 1}, {0, 0.3, 1}, {0, -0.3, 1}};
  const WrenchSet w = sphereWrenches(cap, frictional());
  ASSERT_FALSE(computeGraspWrenchSpace(w).force_closure);
  EXPECT_FALSE(mayBeForceClosure(w));
}

TEST(MayBeForceClosure, TooFewWrenchesAreRejected) {
  EXPECT_FALSE(mayBeForceClosure(WrenchSet(6, 0)));
  WrenchSet w(6, 6);
  w.setIdentity();
  EXPECT_FALSE(mayBeForceClosure(w));
}

TEST(MayBeForceClosure, SimplexAroundTheOriginMayBe) {
  WrenchSet w(6, 7);
  w.leftCols<6>().setIdentity();
  w.col(6) = -Wrench::Ones();
  EXPECT_TRUE(mayBeForceClosure(w));
  EXPECT_TRUE(computeGraspWrenchSpace(w).force_closure);
}

TEST(MayBeForceClosure, OriginOnAFacetIsRejected) {
  // Nothing pushes along -e6: the origin lies on the facet w6 = 0.
  WrenchSet w(6, 7);
  w.leftCols<6>().setIdentity();
  w.col(6) = -Wrench::Ones();
  w(5, 6) = 0.0;
  EXPECT_FALSE(mayBeForceClosure(w));
  EXPECT_FALSE(computeGraspWrenchSpace(w).force_closure);
}

TEST(MayBeForceClosure, CrossPolytopeMayBe) {
  WrenchSet w(6, 12);
  w.leftCols<6>().setIdentity();
  w.rightCols<6>() = -Eigen::Matrix<double, 6, 6>::Identity();
  EXPECT_TRUE(mayBeForceClosure(w));
}

TEST(MayBeForceClosure, FlatSetIsRejected) {
  // Two antipodal frictional contacts on a sphere about its centre: no torque
  // about the contact axis, so the wrenches span only 5 dimensions even
  // though the origin is inside their hull.
  const WrenchSet w = sphereWrenches({{0, 0, 1}, {0, 0, -1}}, frictional());
  EXPECT_FALSE(computeGraspWrenchSpace(w).force_closure);
  EXPECT_FALSE(mayBeForceClosure(w));
}

TEST(MayBeForceClosure, ShiftedOriginIsJudgedByItsPosition) {
  // A cross-polytope translated by t: the origin is inside for |t|_1 < 1.
  WrenchSet w(6, 12);
  w.leftCols<6>().setIdentity();
  w.rightCols<6>() = -Eigen::Matrix<double, 6, 6>::Identity();
  Wrench t = Wrench::Zero();
  t[2] = 0.999;
  EXPECT_TRUE(mayBeForceClosure(w.colwise() + t));
  t[2] = 1.001;
  EXPECT_FALSE(mayBeForceClosure(w.colwise() + t));
}

struct PrecheckTally {
  std::size_t trials = 0, force_closure = 0, false_negatives = 0, non_fc = 0, rejected_non_fc = 0;
};

// Random grasps (uniform distinct vertices), each judged by the pre-check and
// by the full hull, in parallel.
PrecheckTally comparePrecheckWithHull(const GraspableObject& object, const ContactModel& model, std::size_t fingers,
                                      std::size_t trials, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(object.vertexCount()) - 1);
  std::vector<std::vector<int>> grasps(trials);
  for (auto& g : grasps) {
    while (g.size() < fingers) {
      const int v = pick(rng);
      if (std::find(g.begin(), g.end(), v) == g.end()) g.push_back(v);
    }
  }
  const ContactWrenches contact(model, object.frame());
  std::vector<std::uint8_t> maybe(trials), closure(trials);
  tbb::parallel_for(std::size_t{0}, trials, [&](std::size_t t) {
    WrenchSet w(6, static_cast<Eigen::Index>(fingers * contact.perContact()));
    for (std::size_t f = 0; f < fingers; ++f)
      contact.compute(object.position(grasps[t][f]), object.normal(grasps[t][f]), w,
                      static_cast<Eigen::Index>(f * contact.perContact()));
    maybe[t] = mayBeForceClosure(w);
    closure[t] = computeGraspWrenchSpace(w).force_closure;
  });
  PrecheckTally tally;
  tally.trials = trials;
  for (std::size_t t = 0; t < trials; ++t) {
    if (closure[t]) {
      ++tally.force_closure;
      if (!maybe[t]) ++tally.false_negatives;
    } else {
      ++tally.non_fc;
      if (!maybe[t]) ++tally.rejected_non_fc;
    }
  }
  return tally;
}

void reportTally(const std::string& what, const PrecheckTally& tally) {
  const double rejected = tally.non_fc ? static_cast<double>(tally.rejected_non_fc) / tally.non_fc : 1.0;
  std::printf("[ precheck ] %s: %zu grasps, %zu force closure, %zu false negatives, %.1f%% of %zu non-FC rejected\n",
              what.c_str(), tally.trials, tally.force_closure, tally.false_negatives, 100.0 * rejected, tally.non_fc);
}

TEST(MayBeForceClosure, NeverRejectsAForceClosureGraspOnASphere) {
  const TriangleMesh sphere = geodesicSphere(2, 0.05);
  const GraspableObject object = GraspableObject::withDefaultFrame(sphere);
  ContactModel soft = frictional(0.5, 6);
  soft.type = ContactType::SoftFinger;
  ContactModel frictionless;
  frictionless.type = ContactType::Frictionless;
  const std::vector<std::pair<ContactModel, std::size_t>> settings = {
      {frictional(), 4}, {frictional(0.3, 4), 3}, {soft, 2}, {frictionless, 7}};
  for (std::size_t s = 0; s < settings.size(); ++s) {
    const PrecheckTally tally = comparePrecheckWithHull(object, settings[s].first, settings[s].second, 400, 7 + s);
    reportTally("sphere setting " + std::to_string(s), tally);
    EXPECT_EQ(tally.false_negatives, 0u) << "setting " << s;
  }
}

// ---------------------------------------------------------------------------
// Sampling.

TEST(SampleForceClosureGrasps, RejectsTooFewFingersOrVertices) {
  const TriangleMesh sphere = geodesicSphere(1, 0.05);
  GraspSamplingParameters params;
  params.fingers = 1;
  EXPECT_THROW(sampleForceClosureGrasps(GraspableObject::withDefaultFrame(sphere), frictional(), params), InputError);

  std::vector<std::uint8_t> mask(sphere.vertexCount(), 1);
  mask[0] = mask[1] = mask[2] = 0;
  const GraspableObject three = GraspableObject::withDefaultFrame(sphere, mask);
  params.fingers = 4;
  EXPECT_THROW(sampleForceClosureGrasps(three, frictional(), params), InputError);
}

TEST(SampleForceClosureGrasps, GraspsAreDistinctAllowedAndForceClosure) {
  const TriangleMesh sphere = geodesicSphere(2, 0.05);
  std::vector<std::uint8_t> mask(sphere.vertexCount(), 0);
  for (std::size_t v = 0; v < mask.size(); v += 3) mask[v] = 1;
  const GraspableObject object = GraspableObject::withDefaultFrame(sphere, mask);
  GraspSamplingParameters params;
  params.fingers = 3;
  params.count = 30;
  params.min_epsilon = 0.05;
  GraspSamplingStatistics stats;
  const auto grasps = sampleForceClosureGrasps(object, frictional(), params, &stats);
  ASSERT_EQ(grasps.size(), params.count);
  for (const SampledGrasp& g : grasps) {
    ASSERT_EQ(g.contacts.size(), params.fingers);
    EXPECT_EQ(std::set<int>(g.contacts.begin(), g.contacts.end()).size(), params.fingers);
    for (int c : g.contacts) EXPECT_FALSE(object.excluded(static_cast<std::size_t>(c))) << c;
    const GraspWrenchSpace gws = graspWrenchSpace(object, g.contacts, frictional());
    EXPECT_TRUE(gws.force_closure);
    EXPECT_GE(g.epsilon, params.min_epsilon);
    EXPECT_DOUBLE_EQ(g.epsilon, gws.epsilon);
  }
  EXPECT_GE(stats.attempts, params.count);
  EXPECT_EQ(stats.rejected_by_precheck + stats.hulls_built, stats.attempts);
  EXPECT_GE(stats.hulls_built, params.count);
}

TEST(SampleForceClosureGrasps, SameSeedSameGraspsOtherSeedOtherGrasps) {
  const TriangleMesh sphere = geodesicSphere(2, 0.05);
  const GraspableObject object = GraspableObject::withDefaultFrame(sphere);
  GraspSamplingParameters params;
  params.count = 20;
  params.seed = 42;
  const auto first = sampleForceClosureGrasps(object, frictional(), params);
  const auto again = sampleForceClosureGrasps(object, frictional(), params);
  params.seed = 43;
  const auto other = sampleForceClosureGrasps(object, frictional(), params);
  ASSERT_EQ(first.size(), 20u);
  ASSERT_EQ(again.size(), 20u);
  ASSERT_EQ(other.size(), 20u);
  std::size_t same = 0;
  for (std::size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(first[i].contacts, again[i].contacts);
    EXPECT_EQ(first[i].epsilon, again[i].epsilon);
    same += first[i].contacts == other[i].contacts;
  }
  EXPECT_LT(same, 2u);
}

TEST(SampleForceClosureGrasps, ThreadCountDoesNotChangeTheResult) {
  const TriangleMesh sphere = geodesicSphere(3, 0.05);
  std::vector<std::uint8_t> mask(sphere.vertexCount(), 0);
  for (std::size_t v = 0; v < mask.size(); v += 2) mask[v] = 1;
  const GraspableObject object = GraspableObject::withDefaultFrame(sphere, mask);
  GraspSamplingParameters params;
  params.count = 60;
  params.seed = 9;
  params.min_epsilon = 0.1;  // rejects some hulls too, so every counter moves
  auto run = [&](int threads, GraspSamplingStatistics& stats) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return sampleForceClosureGrasps(object, frictional(), params, &stats);
  };
  GraspSamplingStatistics one_stats, two_stats, four_stats;
  const auto one = run(1, one_stats);
  const auto two = run(2, two_stats);
  const auto four = run(4, four_stats);
  ASSERT_EQ(one.size(), params.count);
  ASSERT_EQ(two.size(), one.size());
  ASSERT_EQ(four.size(), one.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i].contacts, two[i].contacts);
    EXPECT_EQ(one[i].epsilon, two[i].epsilon);
    EXPECT_EQ(one[i].contacts, four[i].contacts);
  }
  EXPECT_EQ(one_stats.attempts, two_stats.attempts);
  EXPECT_EQ(one_stats.rejected_by_precheck, two_stats.rejected_by_precheck);
  EXPECT_EQ(one_stats.hulls_built, two_stats.hulls_built);
  EXPECT_EQ(one_stats.attempts, four_stats.attempts);
}

TEST(SampleForceClosureGrasps, StopsAfterMaxAttempts) {
  const TriangleMesh sphere = geodesicSphere(2, 0.05);
  const GraspableObject object = GraspableObject::withDefaultFrame(sphere);
  GraspSamplingParameters params;
  params.count = 1000000;
  params.max_attempts = 300;
  GraspSamplingStatistics stats;
  const auto grasps = sampleForceClosureGrasps(object, frictional(), params, &stats);
  EXPECT_EQ(stats.attempts, 300u);
  EXPECT_LT(grasps.size(), 300u);
  EXPECT_GT(grasps.size(), 0u);
  EXPECT_GE(stats.time_ms, 0.0);

  // A prefix of the attempts gives a prefix of the grasps.
  params.max_attempts = 150;
  const auto fewer = sampleForceClosureGrasps(object, frictional(), params);
  ASSERT_LE(fewer.size(), grasps.size());
  for (std::size_t i = 0; i < fewer.size(); ++i) EXPECT_EQ(fewer[i].contacts, grasps[i].contacts);
}

TEST(SampleForceClosureGrasps, OneSidedObjectGivesNothing) {
  // Only a polar cap is allowed: no grasp there can be force closure, and the
  // pre-check should spare nearly every hull.
  const TriangleMesh sphere = geodesicSphere(3, 0.05);
  std::vector<std::uint8_t> mask(sphere.vertexCount(), 1);
  for (std::size_t v = 0; v < mask.size(); ++v)
    if (sphere.vertices.normals[v].z() > 0.9) mask[v] = 0;
  const GraspableObject object = GraspableObject::withDefaultFrame(sphere, mask);
  GraspSamplingParameters params;
  params.count = 5;
  params.max_attempts = 2000;
  GraspSamplingStatistics stats;
  const auto grasps = sampleForceClosureGrasps(object, frictional(), params, &stats);
  EXPECT_TRUE(grasps.empty());
  EXPECT_EQ(stats.attempts, 2000u);
  EXPECT_EQ(stats.rejected_by_precheck, 2000u);
}

// ---------------------------------------------------------------------------
// Real models.

std::string modelPath(const std::string& name) {
  return std::string(ICRKIT_SHARED_DATA_DIR) + "/icr-models/" + name + ".obj";
}

TEST(SampleForceClosureGrasps, CokeBottleFourFingers) {
  const std::string path = modelPath("CokePlasticSmall_5k");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not found";
  const TriangleMesh mesh = io::readTriangleMesh(path);
  const GraspableObject object = GraspableObject::withDefaultFrame(mesh);
  GraspSamplingParameters params;
  params.count = 40;
  GraspSamplingStatistics stats;
  const auto grasps = sampleForceClosureGrasps(object, frictional(), params, &stats);
  ASSERT_EQ(grasps.size(), params.count);
  for (const SampledGrasp& g : grasps) {
    const GraspWrenchSpace gws = graspWrenchSpace(object, g.contacts, frictional());
    EXPECT_TRUE(gws.force_closure);
    EXPECT_DOUBLE_EQ(g.epsilon, gws.epsilon);
  }
  std::printf("[ sampling ] Coke, 4 fingers: %zu grasps from %zu attempts (%zu pre-check rejections, %zu hulls) in "
              "%.1f ms\n",
              grasps.size(), stats.attempts, stats.rejected_by_precheck, stats.hulls_built, stats.time_ms);
}

TEST(MayBeForceClosure, NeverRejectsAForceClosureGraspOnRealModels) {
  std::size_t models = 0;
  for (const std::string name : {"CokePlasticSmall_5k", "Fish_5k", "RedCup_5k"}) {
    const std::string path = modelPath(name);
    if (!std::filesystem::exists(path)) continue;
    ++models;
    const TriangleMesh mesh = io::readTriangleMesh(path);
    const GraspableObject object = GraspableObject::withDefaultFrame(mesh);
    const PrecheckTally tally = comparePrecheckWithHull(object, frictional(), 4, 300, 11);
    reportTally(name, tally);
    EXPECT_EQ(tally.false_negatives, 0u) << name;
    EXPECT_GT(tally.rejected_non_fc, tally.non_fc / 2) << name;
  }
  if (models == 0) GTEST_SKIP() << "no ICR models under " << ICRKIT_SHARED_DATA_DIR << "/icr-models";
}

}  // namespace
}  // namespace icrkit::icr
