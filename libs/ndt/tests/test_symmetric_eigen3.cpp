// Known-answer tests of the closed-form 3x3 symmetric eigen-decomposition.
// Every matrix is built as R diag(l) R^T from chosen eigenvalues, so the
// expected answer is known without trusting another solver.

#include <icrkit/ndt/symmetric_eigen3.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

namespace icrkit::ndt {
namespace {

// "About 1e-12 relative": the largest residual seen over the random
// matrices below is 1.03e-12 (a few ulps of accumulated rounding).
constexpr double kTolerance = 2e-12;

Eigen::Matrix3d randomRotation(std::mt19937_64& rng) {
  // A normalised 4D Gaussian is a uniformly distributed unit quaternion.
  std::normal_distribution<double> gauss;
  Eigen::Quaterniond q(gauss(rng), gauss(rng), gauss(rng), gauss(rng));
  q.normalize();
  return q.toRotationMatrix();
}

Eigen::Matrix3d compose(const Eigen::Matrix3d& r, const Eigen::Vector3d& values) {
  Eigen::Matrix3d a = r * values.asDiagonal() * r.transpose();
  // Exactly symmetric, as a covariance is: the solver may read either triangle.
  return (0.5 * (a + a.transpose())).eval();
}

// The properties every result must have, whatever the matrix: A v = l v,
// orthonormal right-handed or not (only orthonormality is promised), and
// descending values. Tolerances are relative to the largest |eigenvalue|,
// the natural scale of rounding errors in A.
void expectValidDecomposition(const Eigen::Matrix3d& a, const SymmetricEigen3& e, double tolerance,
                              const std::string& what) {
  SCOPED_TRACE(what);
  const double scale = std::max(a.cwiseAbs().maxCoeff(), e.values.cwiseAbs().maxCoeff());
  ASSERT_TRUE(e.values.allFinite());
  ASSERT_TRUE(e.vectors.allFinite());
  EXPECT_GE(e.values(0), e.values(1));
  EXPECT_GE(e.values(1), e.values(2));
  const Eigen::Matrix3d gram = e.vectors.transpose() * e.vectors;
  EXPECT_LE((gram - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), tolerance) << "V^T V =\n" << gram;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d residual = a * e.vectors.col(k) - e.values(k) * e.vectors.col(k);
    if (scale > 0) {
      EXPECT_LE((residual / scale).norm(), tolerance) << "eigenpair " << k << ", value " << e.values(k);
    }
  }
}

void expectValues(const SymmetricEigen3& e, const Eigen::Vector3d& sorted, double tolerance) {
  const double scale = sorted.cwiseAbs().maxCoeff();
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(e.values(k), sorted(k), tolerance * scale) << "value " << k;
}

TEST(SymmetricEigen3, DiagonalMatrixGivesItsEntriesSortedAndTheAxes) {
  const Eigen::Matrix3d a = Eigen::Vector3d(2.0, 5.0, -1.0).asDiagonal();
  const SymmetricEigen3 e = eigenSymmetric3(a);
  expectValues(e, Eigen::Vector3d(5.0, 2.0, -1.0), 1e-14);
  // The eigenvectors are the axes up to sign: y, x, z.
  EXPECT_NEAR(std::abs(e.vectors(1, 0)), 1.0, 1e-14);
  EXPECT_NEAR(std::abs(e.vectors(0, 1)), 1.0, 1e-14);
  EXPECT_NEAR(std::abs(e.vectors(2, 2)), 1.0, 1e-14);
  expectValidDecomposition(a, e, 1e-13, "diag(2, 5, -1)");
}

TEST(SymmetricEigen3, RandomlyRotatedDiagonalMatricesAreRecovered) {
  std::mt19937_64 rng(20240601);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    const Eigen::Matrix3d r = randomRotation(rng);
    const Eigen::Vector3d unsorted(value(rng), value(rng), value(rng));
    const Eigen::Matrix3d a = compose(r, unsorted);
    Eigen::Vector3d l = unsorted;
    std::sort(l.data(), l.data() + 3, std::greater<>());
    const SymmetricEigen3 e = eigenSymmetric3(a);
    expectValues(e, l, kTolerance);
    expectValidDecomposition(a, e, kTolerance, "trial " + std::to_string(trial));
    // Well-separated values: each vector is the rotated axis up to sign.
    const double gap = std::min(l(0) - l(1), l(1) - l(2));
    if (gap > 1e-2) {
      for (int k = 0; k < 3; ++k) {
        int axis = 0;  // the column of r that carries the k-th largest value
        while (unsorted(axis) != l(k)) ++axis;
        EXPECT_NEAR(std::abs(e.vectors.col(k).dot(r.col(axis))), 1.0, 1e-9) << "trial " << trial << " vector " << k;
      }
    }
  }
}

TEST(SymmetricEigen3, CovarianceOfAFlatWindowGivesTheNormalAsV3) {
  // What the smoother feeds it: two large, one tiny eigenvalue (a disc). The
  // third vector must be the disc normal even when l3 is 1e-10 of l1.
  std::mt19937_64 rng(7);
  for (double ratio : {1e-2, 1e-6, 1e-10, 0.0}) {
    for (int trial = 0; trial < 200; ++trial) {
      const Eigen::Matrix3d r = randomRotation(rng);
      const Eigen::Vector3d l(4e-6, 3e-6, 4e-6 * ratio);  // m^2: a window of a few mm
      const Eigen::Matrix3d a = compose(r, l);
      const SymmetricEigen3 e = eigenSymmetric3(a);
      expectValidDecomposition(a, e, kTolerance, "ratio " + std::to_string(ratio));
      EXPECT_NEAR(std::abs(e.vectors.col(2).dot(r.col(2))), 1.0, 1e-9) << "ratio " << ratio;
    }
  }
}

TEST(SymmetricEigen3, DiscWithTwoEqualLargeValuesHasTheUniqueNormalAsV3) {
  // l1 = l2 > l3: the window of an evenly sampled flat patch, the common case.
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 500; ++trial) {
    const Eigen::Matrix3d r = randomRotation(rng);
    const Eigen::Matrix3d a = compose(r, Eigen::Vector3d(2.0, 2.0, 0.5));
    const SymmetricEigen3 e = eigenSymmetric3(a);
    expectValues(e, Eigen::Vector3d(2.0, 2.0, 0.5), kTolerance);
    expectValidDecomposition(a, e, kTolerance, "disc, trial " + std::to_string(trial));
    EXPECT_NEAR(std::abs(e.vectors.col(2).dot(r.col(2))), 1.0, kTolerance);
  }
}

TEST(SymmetricEigen3, NeedleWithTwoEqualSmallValuesHasTheUniqueAxisAsV1) {
  // l1 > l2 = l3: a window along a scan line or a thin wire.
  std::mt19937_64 rng(12);
  for (int trial = 0; trial < 500; ++trial) {
    const Eigen::Matrix3d r = randomRotation(rng);
    const Eigen::Matrix3d a = compose(r, Eigen::Vector3d(3.0, 1.0, 1.0));
    const SymmetricEigen3 e = eigenSymmetric3(a);
    expectValues(e, Eigen::Vector3d(3.0, 1.0, 1.0), kTolerance);
    expectValidDecomposition(a, e, kTolerance, "needle, trial " + std::to_string(trial));
    EXPECT_NEAR(std::abs(e.vectors.col(0).dot(r.col(0))), 1.0, kTolerance) << "trial " << trial;
  }
}

TEST(SymmetricEigen3, NearlyRepeatedValuesKeepSmallResiduals) {
  // Gaps far below what a cross product of rows can resolve: the vectors
  // inside the near-eigenspace are arbitrary, but A v = l v must still hold.
  std::mt19937_64 rng(13);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Matrix3d r = randomRotation(rng);
    for (double gap : {1e-6, 1e-9, 1e-13}) {
      const Eigen::Matrix3d a = compose(r, Eigen::Vector3d(1.0 + gap, 1.0, 0.25));
      expectValidDecomposition(a, eigenSymmetric3(a), kTolerance, "upper gap " + std::to_string(gap));
      const Eigen::Matrix3d b = compose(r, Eigen::Vector3d(1.0, 0.25 + gap, 0.25));
      expectValidDecomposition(b, eigenSymmetric3(b), kTolerance, "lower gap " + std::to_string(gap));
    }
  }
}

TEST(SymmetricEigen3, MultipleOfTheIdentityGivesItsValueThrice) {
  const Eigen::Matrix3d a = 3.5 * Eigen::Matrix3d::Identity();
  const SymmetricEigen3 e = eigenSymmetric3(a);
  expectValues(e, Eigen::Vector3d::Constant(3.5), 1e-15);
  expectValidDecomposition(a, e, 1e-14, "3.5 I");
}

TEST(SymmetricEigen3, ZeroMatrixGivesZeroValuesAndAnOrthonormalBasis) {
  const SymmetricEigen3 e = eigenSymmetric3(Eigen::Matrix3d::Zero());
  EXPECT_EQ(e.values, Eigen::Vector3d::Zero());
  EXPECT_LE((e.vectors.transpose() * e.vectors - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(SymmetricEigen3, TinyAndHugeScalesAreAsAccurateAsUnitScale) {
  // Squares of 1e-200 underflow and of 1e200 overflow: only an
  // implementation that rescales first survives both.
  std::mt19937_64 rng(3);
  for (double scale : {1e-300, 1e-200, 1e-100, 1e-12, 1.0, 1e12, 1e100, 1e200, 1e300}) {
    for (int trial = 0; trial < 50; ++trial) {
      const Eigen::Matrix3d r = randomRotation(rng);
      const Eigen::Vector3d l = Eigen::Vector3d(0.9, 0.4, 0.01) * scale;
      const Eigen::Matrix3d a = compose(r, l);
      const SymmetricEigen3 e = eigenSymmetric3(a);
      expectValues(e, l, kTolerance);
      expectValidDecomposition(a, e, kTolerance, "scale " + std::to_string(scale));
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(std::abs(e.vectors.col(k).dot(r.col(k))), 1.0, 1e-10) << "scale " << scale << " vector " << k;
    }
  }
}

TEST(SymmetricEigen3, NegativeAndIndefiniteMatricesAreSortedBySignedValue) {
  std::mt19937_64 rng(5);
  const Eigen::Matrix3d r = randomRotation(rng);
  const Eigen::Matrix3d a = compose(r, Eigen::Vector3d(-1.0, -7.0, 0.5));
  const SymmetricEigen3 e = eigenSymmetric3(a);
  expectValues(e, Eigen::Vector3d(0.5, -1.0, -7.0), 1e-13);
  expectValidDecomposition(a, e, 1e-12, "indefinite");
}

}  // namespace
}  // namespace icrkit::ndt
