#include <icrkit/core/error.hpp>
#include <icrkit/icr/grasp_wrench_space.hpp>
#include <icrkit/icr/search_zones.hpp>
#include <icrkit/icr/task_wrench_space.hpp>
#include <icrkit/icr/wrench.hpp>

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <random>

using namespace icrkit;
using namespace icrkit::icr;

namespace {
// The 12 points +-e_i: a cross-polytope with 2^6 facets at distance 1/sqrt(6).
WrenchSet crossPolytope() {
  WrenchSet w(6, 12);
  w.setZero();
  for (int i = 0; i < 6; ++i) {
    w(i, 2 * i) = 1;
    w(i, 2 * i + 1) = -1;
  }
  return w;
}
}  // namespace

TEST(ContactModel, FrictionalPrimitivesFollowTheReferenceConvention) {
  ContactModel model;  // frictional, mu 0.8, L 8
  const auto primitives = localPrimitives(model);
  ASSERT_EQ(primitives.size(), 9u);
  EXPECT_EQ(model.wrenchesPerContact(), 9u);
  EXPECT_EQ(primitives[0].force, Eigen::Vector3d(0, 0, 1));
  const double a = std::atan(0.8);
  EXPECT_NEAR(primitives[1].force.x(), -std::sin(a), 1e-15);  // t_0 = -pi
  EXPECT_NEAR(primitives[1].force.y(), 0.0, 1e-15);
  EXPECT_NEAR(primitives[1].force.z(), std::cos(a), 1e-15);
  EXPECT_NEAR(primitives[3].force.y(), -std::sin(a), 1e-15);  // t_2 = -pi/2
  for (const auto& p : primitives) EXPECT_NEAR(p.force.norm(), 1.0, 1e-15);

  ContactModel soft;
  soft.type = ContactType::SoftFinger;
  soft.torsional_friction = 0.5;
  const auto s = localPrimitives(soft);
  ASSERT_EQ(s.size(), 11u);
  EXPECT_EQ(s[9].torsion, 0.5);
  EXPECT_EQ(s[10].torsion, -0.5);

  ContactModel frictionless;
  frictionless.type = ContactType::Frictionless;
  EXPECT_EQ(localPrimitives(frictionless).size(), 1u);

  ContactModel bad;
  bad.friction = -1;
  EXPECT_THROW(bad.validate(), InputError);
  bad = ContactModel();
  bad.cone_edges = 2;
  EXPECT_THROW(bad.validate(), InputError);
}

TEST(ContactModel, RotationFromZIsTheSmallestRotation) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d n = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    const Eigen::Matrix3d r = rotationFromZ(n);
    EXPECT_TRUE((r * Eigen::Vector3d::UnitZ()).isApprox(n, 1e-12));
    EXPECT_TRUE((r.transpose() * r).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
    EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
    // The axis z x n is left fixed.
    const Eigen::Vector3d axis = Eigen::Vector3d::UnitZ().cross(n);
    EXPECT_TRUE((r * axis).isApprox(axis, 1e-12));
  }
  EXPECT_TRUE(rotationFromZ(Eigen::Vector3d::UnitZ()).isIdentity());
  EXPECT_EQ(rotationFromZ(-Eigen::Vector3d::UnitZ()), Eigen::Matrix3d(Eigen::Vector3d(1, -1, -1).asDiagonal()));
}

TEST(Wrench, TorqueAboutTheReferenceScaledByLambda) {
  ContactModel frictionless;
  frictionless.type = ContactType::Frictionless;
  WrenchFrame frame;
  frame.reference_point = Eigen::Vector3d(0, 0, 1);
  frame.lambda = 2.0;
  const ContactWrenches generator(frictionless, frame);
  const WrenchSet w = generator.compute(Eigen::Vector3d(1, 0, 1), Eigen::Vector3d(0, 1, 0));
  ASSERT_EQ(w.cols(), 1);
  Wrench expected;
  expected << 0, 1, 0, 0, 0, 0.5;  // (1,0,0) x (0,1,0) = (0,0,1), / lambda
  EXPECT_TRUE(w.col(0).isApprox(expected, 1e-15));

  const std::vector<Eigen::Vector3d> points{{1, 0, 0}, {-3, 0, 0}, {0, 2, 0}};
  EXPECT_DOUBLE_EQ(makeWrenchFrame(points).lambda, 3.0);
  const WrenchFrame centred = makeWrenchFrame(points, TorqueReference::Centroid);
  EXPECT_TRUE(centred.reference_point.isApprox(Eigen::Vector3d(-2.0 / 3, 2.0 / 3, 0)));
  EXPECT_THROW(makeWrenchFrame({}), InputError);
}

TEST(GraspWrenchSpace, CrossPolytopeKnownAnswer) {
  const GraspWrenchSpace gws = computeGraspWrenchSpace(crossPolytope());
  ASSERT_TRUE(gws.force_closure) << gws.reason;
  EXPECT_EQ(gws.facetCount(), 64u);
  EXPECT_NEAR(gws.epsilon, 1.0 / std::sqrt(6.0), 1e-12);
  EXPECT_EQ(gws.hull_vertices.size(), 12u);
  for (std::size_t f = 0; f < gws.facetCount(); ++f) {
    EXPECT_EQ(gws.facet_vertices[f].size(), 6u);
    EXPECT_NEAR(gws.normals.col(static_cast<Eigen::Index>(f)).norm(), 1.0, 1e-12);
  }
}

TEST(GraspWrenchSpace, DegenerateSetsAreNotForceClosureAndQhullStaysQuiet) {
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  // Too few wrenches.
  GraspWrenchSpace gws = computeGraspWrenchSpace(crossPolytope().leftCols(6));
  EXPECT_FALSE(gws.force_closure);
  EXPECT_NE(gws.reason.find("at least 7"), std::string::npos);
  // Lower-dimensional: the last coordinate is always 0.
  WrenchSet flat = crossPolytope().leftCols(10);
  gws = computeGraspWrenchSpace(flat);
  EXPECT_FALSE(gws.force_closure);
  EXPECT_NE(gws.reason.find("qhull"), std::string::npos) << gws.reason;
  // Full-dimensional but the origin is outside.
  WrenchSet shifted = crossPolytope();
  shifted.row(0).array() += 5.0;
  gws = computeGraspWrenchSpace(shifted);
  EXPECT_FALSE(gws.force_closure);
  EXPECT_LT(gws.epsilon, 0.0);
  // Non-finite.
  WrenchSet bad = crossPolytope();
  bad(3, 3) = std::nan("");
  EXPECT_FALSE(computeGraspWrenchSpace(bad).force_closure);
  EXPECT_EQ(testing::internal::GetCapturedStdout(), "");
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST(GraspWrenchSpace, ParallelHullsAgree) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  std::vector<WrenchSet> sets(64, WrenchSet(6, 30));
  for (auto& s : sets)
    for (Eigen::Index i = 0; i < s.size(); ++i) s.data()[i] = g(rng);
  std::vector<double> serial(sets.size()), parallel(sets.size());
  for (std::size_t i = 0; i < sets.size(); ++i) serial[i] = computeGraspWrenchSpace(sets[i]).epsilon;
  tbb::parallel_for(std::size_t(0), sets.size(), [&](std::size_t i) { parallel[i] = computeGraspWrenchSpace(sets[i]).epsilon; });
  EXPECT_EQ(serial, parallel);
}

TEST(TaskWrenchSpace, BallAndPolytopeMustFitInsideTheGws) {
  const GraspWrenchSpace gws = computeGraspWrenchSpace(crossPolytope());
  EXPECT_NO_THROW(TaskWrenchSpace::ball(0.4).requireInside(gws));
  EXPECT_THROW(TaskWrenchSpace::ball(0.41).requireInside(gws), InputError);  // 1/sqrt(6) = 0.408
  EXPECT_THROW(TaskWrenchSpace::ball(0.0), InputError);
  WrenchSet disturbances = WrenchSet::Zero(6, 2);
  disturbances(0, 0) = 0.9;
  disturbances(0, 1) = -0.9;
  const TaskWrenchSpace tws = TaskWrenchSpace::polytope(disturbances);
  EXPECT_NO_THROW(tws.requireInside(gws));  // along an axis the hull reaches 1
  disturbances(0, 0) = 1.1;
  EXPECT_THROW(TaskWrenchSpace::polytope(disturbances).requireInside(gws), InputError);
  Wrench u = Wrench::Zero();
  u(0) = 1;
  EXPECT_DOUBLE_EQ(tws.support(u), 0.9);
}

TEST(SearchZones, EachHullVertexOwnsItsIncidentFacets) {
  const GraspWrenchSpace gws = computeGraspWrenchSpace(crossPolytope());
  // 12 wrenches as 6 "fingers" of 2 wrenches each.
  const SearchZones zones = computeSearchZones(gws, TaskWrenchSpace::ball(0.2), 6, 2);
  ASSERT_EQ(zones.by_finger.size(), 6u);
  for (const auto& finger_zones : zones.by_finger) {
    ASSERT_EQ(finger_zones.size(), 2u);
    for (const SearchZone& zone : finger_zones) EXPECT_EQ(zone.facets.size(), 32u);  // each vertex of the cross-polytope
  }
  // A wrench at the hull vertex e_0 lies in its own zone, the origin in none.
  ZoneTester tester(zones);
  WrenchSet near_vertex = WrenchSet::Zero(6, 2);
  near_vertex(0, 0) = 1.0;
  near_vertex(0, 1) = -1.0;
  EXPECT_TRUE(tester.qualifies(0, near_vertex));
  EXPECT_FALSE(tester.qualifies(0, WrenchSet::Zero(6, 2)));
  EXPECT_FALSE(tester.qualifies(1, near_vertex));
}

TEST(GraspWrenchSpace, ContainmentCheckFindsAWrenchBeyondAFacet) {
  const WrenchSet vertices = crossPolytope();
  const GraspWrenchSpace gws = computeGraspWrenchSpace(vertices);
  ASSERT_TRUE(gws.force_closure);
  EXPECT_TRUE(hullContains(gws, vertices));
  WrenchSet probe = WrenchSet::Zero(6, 2);
  probe(0, 0) = 0.5;
  probe(3, 1) = -1.0;
  EXPECT_TRUE(hullContains(gws, probe));
  probe(3, 1) = -1.001;
  EXPECT_FALSE(hullContains(gws, probe));
  EXPECT_TRUE(hullContains(gws, probe, 1e-2));
}

TEST(GraspWrenchSpace, UnmergedDefaultHullGivesTheSameEpsilonAsMergedHull) {
  HullParameters merged_only;
  merged_only.qhull_options = "Qt Qx";
  merged_only.fallback_options.clear();
  std::mt19937 rng(9);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 20; ++trial) {
    WrenchSet w(6, 36);
    for (Eigen::Index i = 0; i < w.size(); ++i) w.data()[i] = g(rng);
    const GraspWrenchSpace merged = computeGraspWrenchSpace(w, merged_only);
    const GraspWrenchSpace unmerged = computeGraspWrenchSpace(w);
    EXPECT_EQ(merged.qhull_options, "Qt Qx");
    EXPECT_EQ(unmerged.qhull_options, "Q0");
    EXPECT_EQ(merged.force_closure, unmerged.force_closure);
    EXPECT_NEAR(merged.epsilon, unmerged.epsilon, 1e-12);
    EXPECT_EQ(merged.hull_vertices, unmerged.hull_vertices);
    EXPECT_EQ(merged.facetCount(), unmerged.facetCount());
  }
  // A degenerate set fails both attempts and reports the last one.
  WrenchSet flat = crossPolytope().leftCols(10);
  const GraspWrenchSpace none = computeGraspWrenchSpace(flat);
  EXPECT_FALSE(none.force_closure);
  EXPECT_EQ(none.qhull_options, "Qt Qx");
  // A first hull the containment check rejects (here: any, with a negative
  // tolerance) is rebuilt with the fallback options.
  HullParameters suspicious;
  suspicious.convexity_tolerance = -1.0;
  const GraspWrenchSpace rebuilt = computeGraspWrenchSpace(crossPolytope(), suspicious);
  EXPECT_EQ(rebuilt.qhull_options, "Qt Qx");
  EXPECT_TRUE(rebuilt.force_closure);
  EXPECT_NEAR(rebuilt.epsilon, 1.0 / std::sqrt(6.0), 1e-12);
}

namespace icrkit::icr {
namespace {

TEST(SearchZones, NeighbourEvidenceNeverChangesTheAnswer) {
  // A random 4 x 9 wrench GWS, zones for a ball of half its epsilon; parents
  // that qualify, children moved from them by random steps from tiny to
  // large: with the parent's evidence the answer must be the full test's.
  std::mt19937 rng(21);
  std::normal_distribution<double> g;
  WrenchSet w(6, 36);
  for (Eigen::Index i = 0; i < w.size(); ++i) w.data()[i] = g(rng);
  const GraspWrenchSpace gws = computeGraspWrenchSpace(w);
  ASSERT_TRUE(gws.force_closure);
  const SearchZones zones = computeSearchZones(gws, TaskWrenchSpace::ball(0.5 * gws.epsilon), 4, 9);
  ZoneTester tester(zones);
  std::size_t qualifying_children = 0, checked = 0;
  for (std::size_t finger = 0; finger < 4; ++finger) {
    const std::size_t count = tester.zoneCount(finger);
    std::vector<Eigen::Index> wrench(count), child_wrench(count);
    std::vector<double> slack(count), child_slack(count);
    for (int trial = 0; trial < 200; ++trial) {
      // A parent near the finger's own wrenches (which lie in their zones).
      WrenchSet parent = w.middleCols(static_cast<Eigen::Index>(9 * finger), 9);
      for (Eigen::Index i = 0; i < parent.size(); ++i) parent.data()[i] += 0.02 * g(rng);
      if (!tester.qualifies(finger, parent, nullptr, wrench.data(), slack.data())) continue;
      for (std::size_t z = 0; z < count; ++z) EXPECT_GE(slack[z], 0.0);
      ZoneTester::Evidence evidence{&parent, wrench.data(), slack.data()};
      for (const double step : {1e-6, 1e-3, 1e-2, 0.05, 0.2}) {
        WrenchSet child = parent;
        for (Eigen::Index i = 0; i < child.size(); ++i) child.data()[i] += step * g(rng);
        const bool full = tester.qualifies(finger, child);
        const bool fast = tester.qualifies(finger, child, &evidence, child_wrench.data(), child_slack.data());
        EXPECT_EQ(full, fast) << "finger " << finger << " step " << step;
        ++checked;
        qualifying_children += full ? 1 : 0;
        if (fast) {
          // The child's own evidence is honest: each named wrench clears
          // every facet of its zone by at least the stated slack.
          for (std::size_t z = 0; z < count; ++z) {
            EXPECT_GE(child_slack[z], 0.0);
            const Wrench c = child.col(child_wrench[z]);
            for (int f : zones.by_finger[finger][z].facets)
              EXPECT_GE(zones.normals.col(f).dot(c) - zones.thresholds[static_cast<std::size_t>(f)],
                        child_slack[z] - 1e-9);
          }
        }
      }
    }
  }
  EXPECT_GT(checked, 500u);
  EXPECT_GT(qualifying_children, 100u);
  EXPECT_GT(tester.zonesOnEvidence(), 500u);  // the shortcut was taken, not just the full test
}

}  // namespace
}  // namespace icrkit::icr
