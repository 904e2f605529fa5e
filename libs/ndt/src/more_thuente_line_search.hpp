#pragma once
/// \file
/// The More-Thuente line search (More & Thuente, "Line search algorithms with
/// guaranteed sufficient decrease", ACM TOMS 20(3), 1994): finds a step a in
/// [a_min, a_max] with the strong Wolfe conditions
///   phi(a) <= phi(0) + ftol a phi'(0)  and  |phi'(a)| <= gtol |phi'(0)|
/// by safeguarded cubic / quadratic interpolation. Private to the ndt library.

#include <functional>

namespace icrkit::ndt {

struct LineSearchParameters {
  double ftol = 1e-4;  ///< sufficient decrease
  double gtol = 0.9;   ///< curvature (0.9: loose, as suits Newton directions)
  double xtol = 1e-8;  ///< relative width of the bracket at which to give up
  double step_min = 0.0;
  double step_max = 1.0;
  int max_evaluations = 10;
};

struct LineSearchResult {
  double step = 0.0;
  double value = 0.0;       ///< phi(step)
  double derivative = 0.0;  ///< phi'(step)
  int evaluations = 0;
  bool wolfe = false;  ///< both conditions hold at `step`
};

/// `phi(a, &derivative)` returns phi(a) and sets phi'(a). `initial_step` is
/// clamped to [step_min, step_max]; phi'(0) must be negative (a descent
/// direction). Returns the best step found when the evaluations run out.
LineSearchResult moreThuenteLineSearch(const std::function<double(double, double*)>& phi, double value0,
                                       double derivative0, double initial_step, const LineSearchParameters& params);

}  // namespace icrkit::ndt
