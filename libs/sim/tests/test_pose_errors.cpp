// The robot-reported pose errors (sim::PoseErrorModel): the industrial
// arm's, unchanged, and the mobile manipulator's independent per-view
// errors, with their statistics over many views.

#include <icrkit/sim/acquisition.hpp>
#include <icrkit/sim/cad_objects.hpp>
#include <icrkit/sim/rawlog_writer.hpp>

#include <icrkit/core/error.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iostream>
#include <vector>

namespace icrkit::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The error of each view in its camera frame, T_true^-1 T_reported, as
// translation and rotation vector: with the error right-multiplied, this
// is exactly the drawn error.
struct ViewErrors {
  std::vector<std::array<double, 3>> translation, rotation;
};
ViewErrors viewErrors(const std::vector<View>& views) {
  ViewErrors e;
  for (const View& v : views) {
    const Eigen::Isometry3d error = v.true_camera.inverse() * v.reported_camera;
    const Eigen::AngleAxisd angle_axis(error.linear());
    const Eigen::Vector3d t = error.translation(), r = angle_axis.angle() * angle_axis.axis();
    e.translation.push_back({t.x(), t.y(), t.z()});
    e.rotation.push_back({r.x(), r.y(), r.z()});
  }
  return e;
}

double mean(const std::vector<std::array<double, 3>>& samples, int axis) {
  double sum = 0;
  for (const auto& s : samples) sum += s[axis];
  return sum / static_cast<double>(samples.size());
}

double sigma(const std::vector<std::array<double, 3>>& samples, int axis) {
  const double m = mean(samples, axis);
  double sum = 0;
  for (const auto& s : samples) sum += (s[axis] - m) * (s[axis] - m);
  return std::sqrt(sum / static_cast<double>(samples.size() - 1));
}

// Pearson correlation of each view's error with the next view's.
double lagOneCorrelation(const std::vector<std::array<double, 3>>& samples, int axis) {
  const double m = mean(samples, axis);
  double cross = 0, square = 0;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    square += (samples[k][axis] - m) * (samples[k][axis] - m);
    if (k + 1 < samples.size()) cross += (samples[k][axis] - m) * (samples[k + 1][axis] - m);
  }
  return cross / square;
}

AcquisitionParameters manyViews(const PoseErrorModel& errors, std::uint64_t seed) {
  AcquisitionParameters params;
  params.setup = Setup::A;
  params.views = 4000;
  params.errors = errors;
  params.seed = seed;
  return params;
}

const Eigen::AlignedBox3d kBox(Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.1));

TEST(PoseErrors, MobileModelHasItsSigmaPerAxisIndependentPerView) {
  const std::vector<View> views = planViews(manyViews(mobilePoseErrors(), 1), kBox);
  const ViewErrors e = viewErrors(views);
  const double want_t = 0.003, want_r = 0.5 * kPi / 180.0;
  const double n = static_cast<double>(views.size());
  for (int axis = 0; axis < 3; ++axis) {
    const double st = sigma(e.translation, axis), sr = sigma(e.rotation, axis);
    const double ct = lagOneCorrelation(e.translation, axis), cr = lagOneCorrelation(e.rotation, axis);
    std::cout << "mobile, axis " << axis << ": sigma " << st * 1e3 << " mm, " << sr * 180.0 / kPi
              << " deg; lag-1 correlation " << ct << ", " << cr << "\n";
    EXPECT_NEAR(st, want_t, 0.15 * want_t) << axis;
    EXPECT_NEAR(sr, want_r, 0.15 * want_r) << axis;
    // Nothing fixed: the mean is zero within 4 standard errors.
    EXPECT_NEAR(mean(e.translation, axis), 0.0, 4.0 * want_t / std::sqrt(n)) << axis;
    EXPECT_NEAR(mean(e.rotation, axis), 0.0, 4.0 * want_r / std::sqrt(n)) << axis;
    // Independent: 1/sqrt(n) = 0.016 is the standard error of a zero correlation.
    EXPECT_LT(std::abs(ct), 0.08) << axis;
    EXPECT_LT(std::abs(cr), 0.08) << axis;
  }
}

TEST(PoseErrors, ArmModelsErrorsAreCorrelatedBetweenViews) {
  // The contrast the mobile model is for: the arm's drift grows from view
  // to view and dwarfs its per-view noise, so consecutive views share most
  // of their error.
  const ViewErrors e = viewErrors(planViews(manyViews(armPoseErrors(), 1), kBox));
  EXPECT_GT(lagOneCorrelation(e.translation, 0), 0.9);
}

TEST(PoseErrors, ExplicitSigmasAreDrawnAsGiven) {
  const PoseErrorModel model = parsePoseErrorModel("5mm,1deg");
  EXPECT_EQ(model.name, "custom");
  EXPECT_DOUBLE_EQ(model.noise_translation, 0.005);
  EXPECT_DOUBLE_EQ(model.noise_rotation, kPi / 180.0);
  EXPECT_EQ(model.hand_eye_translation, 0.0);
  EXPECT_EQ(model.drift_rotation, 0.0);
  const ViewErrors e = viewErrors(planViews(manyViews(model, 3), kBox));
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(sigma(e.translation, axis), 0.005, 0.15 * 0.005) << axis;
    EXPECT_NEAR(sigma(e.rotation, axis), kPi / 180.0, 0.15 * kPi / 180.0) << axis;
  }
}

TEST(PoseErrors, DeterministicForASeed) {
  const std::vector<View> a = planViews(manyViews(mobilePoseErrors(), 7), kBox);
  const std::vector<View> b = planViews(manyViews(mobilePoseErrors(), 7), kBox);
  const std::vector<View> c = planViews(manyViews(mobilePoseErrors(), 8), kBox);
  ASSERT_EQ(a.size(), b.size());
  bool differs = false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_TRUE(a[k].reported_camera.matrix() == b[k].reported_camera.matrix()) << k;
    EXPECT_TRUE(a[k].true_camera.matrix() == c[k].true_camera.matrix()) << k;
    differs = differs || !(a[k].reported_camera.matrix() == c[k].reported_camera.matrix());
  }
  EXPECT_TRUE(differs);
}

TEST(PoseErrors, GroundTruthDoesNotDependOnTheModel) {
  const std::vector<View> arm = planViews(manyViews(armPoseErrors(), 1), kBox);
  const std::vector<View> mobile = planViews(manyViews(mobilePoseErrors(), 1), kBox);
  for (std::size_t k = 0; k < arm.size(); ++k) {
    EXPECT_TRUE(arm[k].true_camera.matrix() == mobile[k].true_camera.matrix()) << k;
    EXPECT_EQ(arm[k].timestamp, mobile[k].timestamp) << k;
  }
}

TEST(PoseErrors, ArmDefaultIsUnchanged) {
  const PoseErrorModel arm;
  EXPECT_EQ(arm.name, "arm");
  EXPECT_EQ(arm.noise_translation, 0.0003);
  EXPECT_EQ(arm.noise_rotation, 0.0005);
  EXPECT_EQ(arm.hand_eye_translation, 0.002);
  EXPECT_EQ(arm.hand_eye_rotation, 0.003);
  EXPECT_EQ(arm.drift_translation, 0.00005);
  EXPECT_EQ(arm.drift_rotation, 0.00005);
  // The first reported sensorPose of `icrkit simulate --object cup --sensor
  // kinect --views 3 --seed 5` as written (reported_poses.txt) before the
  // mobile model existed: the arm's stream of draws is untouched.
  AcquisitionParameters params;
  params.setup = Setup::B;
  params.views = 3;
  params.seed = 5;
  const Eigen::AlignedBox3d cup = makeCadObject(parseCadObject("cup")).vertices.bounds();
  for (const PoseErrorModel& model : {PoseErrorModel{}, parsePoseErrorModel("arm"), parsePoseErrorModel("ARM")}) {
    params.errors = model;
    const Eigen::Isometry3d reported = mrptSensorPose(planViews(params, cup)[0].reported_camera);
    const Eigen::Quaterniond q(reported.linear());
    EXPECT_NEAR(reported.translation().x(), 0.6286022208772855, 1e-12);
    EXPECT_NEAR(reported.translation().y(), -0.0011765310547347673, 1e-12);
    EXPECT_NEAR(reported.translation().z(), 0.3503746238974543, 1e-12);
    const double sign = q.w() < 0 ? -1.0 : 1.0;
    EXPECT_NEAR(sign * q.x(), -0.22194413992027953, 1e-12);
    EXPECT_NEAR(sign * q.y(), -0.0007404297397132793, 1e-12);
    EXPECT_NEAR(sign * q.z(), 0.9750590719857998, 1e-12);
    EXPECT_NEAR(sign * q.w(), 0.0002380273913494901, 1e-12);
  }
}

TEST(PoseErrors, ParsesModelsAndUnits) {
  EXPECT_EQ(parsePoseErrorModel("mobile").name, "mobile");
  EXPECT_EQ(parsePoseErrorModel("Mobile").noise_translation, 0.003);
  EXPECT_EQ(parsePoseErrorModel("none").noise_rotation, 0.0);
  EXPECT_EQ(parsePoseErrorModel("none").hand_eye_translation, 0.0);
  const PoseErrorModel cm = parsePoseErrorModel("0.5cm,8.7mrad");
  EXPECT_DOUBLE_EQ(cm.noise_translation, 0.005);
  EXPECT_DOUBLE_EQ(cm.noise_rotation, 0.0087);
  const PoseErrorModel si = parsePoseErrorModel("0.002m,0.01rad");
  EXPECT_DOUBLE_EQ(si.noise_translation, 0.002);
  EXPECT_DOUBLE_EQ(si.noise_rotation, 0.01);
  EXPECT_EQ(parsePoseErrorModel("0mm,0deg").noise_translation, 0.0);
  for (const char* bad : {"", "wobbly", "5,1deg", "5mm,1", "5mm", "5mm,1deg,1deg", "-1mm,1deg", "5mm,-1deg",
                          "nanmm,1deg", "infmm,1deg", "5 mm,1deg", "5mm,1degs", "1deg,5mm", "5km,1deg"}) {
    try {
      parsePoseErrorModel(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& error) {
      EXPECT_EQ(error.source(), "pose error model") << bad;
    }
  }
  EXPECT_THROW(independentPoseErrors(-0.001, 0.0), InputError);
  EXPECT_THROW(independentPoseErrors(0.001, std::nan("")), InputError);
}

TEST(PoseErrors, PlanViewsRejectsNegativeOrNonFiniteErrors) {
  AcquisitionParameters params;
  params.views = 2;
  params.errors.hand_eye_translation = -0.001;
  EXPECT_THROW(planViews(params, kBox), InputError);
  params.errors = mobilePoseErrors();
  params.errors.noise_rotation = std::nan("");
  EXPECT_THROW(planViews(params, kBox), InputError);
}

}  // namespace
}  // namespace icrkit::sim
