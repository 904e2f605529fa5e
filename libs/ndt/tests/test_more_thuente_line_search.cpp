// The More-Thuente line search on the test functions of More & Thuente
// (1994), Section 5: the returned step must meet the strong Wolfe conditions,
// from starting steps three orders of magnitude either side of the answer.

#include "more_thuente_line_search.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace icrkit::ndt {
namespace {

// Returns the step; the paper's Tables 1-2 list the step and the number of
// evaluations for each start, which the tests compare against.
LineSearchResult expectStrongWolfe(const std::function<double(double, double*)>& phi, const LineSearchParameters& params,
                                   double start) {
  double g0 = 0.0;
  const double f0 = phi(0.0, &g0);
  const LineSearchResult r = moreThuenteLineSearch(phi, f0, g0, start, params);
  EXPECT_TRUE(r.wolfe) << "start " << start << ": step " << r.step << " after " << r.evaluations << " evaluations";
  EXPECT_LE(r.value, f0 + params.ftol * r.step * g0) << "start " << start;
  EXPECT_LE(std::abs(r.derivative), params.gtol * std::abs(g0)) << "start " << start;
  EXPECT_LE(r.evaluations, params.max_evaluations);
  return r;
}

struct PaperRow {
  double start, step;
  int evaluations;
};

TEST(MoreThuenteLineSearch, Function1FromThePaper) {
  // phi(a) = -a / (a^2 + 2): minimum at sqrt(2).
  const auto phi = [](double a, double* g) {
    const double b = 2.0;
    *g = (a * a - b) / ((a * a + b) * (a * a + b));
    return -a / (a * a + b);
  };
  LineSearchParameters params;
  params.ftol = 1e-3;
  params.gtol = 0.1;
  params.step_max = 1e4;
  params.max_evaluations = 20;
  for (const PaperRow& row : {PaperRow{1e-3, 1.4, 6}, PaperRow{1e-1, 1.4, 3}, PaperRow{1e1, 10, 1}, PaperRow{1e3, 37, 4}}) {
    const LineSearchResult r = expectStrongWolfe(phi, params, row.start);
    EXPECT_NEAR(r.step, row.step, 0.05 * row.step) << "start " << row.start;
    EXPECT_EQ(r.evaluations, row.evaluations) << "start " << row.start;
  }
}

TEST(MoreThuenteLineSearch, Function2FromThePaper) {
  // phi(a) = (a + 0.004)^5 - 2 (a + 0.004)^4: minimum near 1.6.
  const auto phi = [](double a, double* g) {
    const double b = 0.004, x = a + b;
    *g = 5 * std::pow(x, 4) - 8 * std::pow(x, 3);
    return std::pow(x, 5) - 2 * std::pow(x, 4);
  };
  LineSearchParameters params;
  params.ftol = 0.1;
  params.gtol = 0.1;
  params.step_max = 1e4;
  params.max_evaluations = 20;
  for (const PaperRow& row : {PaperRow{1e-3, 1.6, 12}, PaperRow{1e-1, 1.6, 8}, PaperRow{1e1, 1.6, 8}, PaperRow{1e3, 1.6, 11}}) {
    const LineSearchResult r = expectStrongWolfe(phi, params, row.start);
    EXPECT_NEAR(r.step, row.step, 0.05 * row.step) << "start " << row.start;
    EXPECT_EQ(r.evaluations, row.evaluations) << "start " << row.start;
  }
}

TEST(MoreThuenteLineSearch, QuadraticTakesTheFullNewtonStep) {
  // phi(a) = (a - 1)^2: a Newton direction of the right length; step 1 is accepted at once.
  const auto phi = [](double a, double* g) {
    *g = 2 * (a - 1);
    return (a - 1) * (a - 1);
  };
  const LineSearchResult r = moreThuenteLineSearch(phi, 1.0, -2.0, 1.0, LineSearchParameters{});
  EXPECT_TRUE(r.wolfe);
  EXPECT_EQ(r.step, 1.0);
  EXPECT_EQ(r.evaluations, 1);
}

TEST(MoreThuenteLineSearch, AscentDirectionReturnsZeroStep) {
  const auto phi = [](double a, double* g) {
    *g = 1.0;
    return a;
  };
  const LineSearchResult r = moreThuenteLineSearch(phi, 0.0, 1.0, 1.0, LineSearchParameters{});
  EXPECT_EQ(r.step, 0.0);
  EXPECT_EQ(r.evaluations, 0);
}

}  // namespace
}  // namespace icrkit::ndt
