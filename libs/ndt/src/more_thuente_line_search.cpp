#include "more_thuente_line_search.hpp"

#include <algorithm>
#include <cmath>

namespace icrkit::ndt {

namespace {

// One safeguarded step (the "dcstep" of More & Thuente): x is the best step so
// far, y the other end of the interval, t the current trial; returns the next
// trial and updates the interval. The four cases follow the paper's Section 4.
struct Interval {
  double x, fx, gx;
  double y, fy, gy;
  bool bracketed = false;
};

double cubicMinimiser(double a, double fa, double ga, double b, double fb, double gb) {
  // Minimiser of the cubic interpolating f and f' at a and b.
  const double theta = 3.0 * (fa - fb) / (b - a) + ga + gb;
  const double s = std::max({std::abs(theta), std::abs(ga), std::abs(gb)});
  double gamma = s * std::sqrt(std::max(0.0, (theta / s) * (theta / s) - (ga / s) * (gb / s)));
  if (b < a) gamma = -gamma;
  const double p = (gamma - ga) + theta;
  const double q = ((gamma - ga) + gamma) + gb;
  return a + (p / q) * (b - a);
}

double step(Interval& iv, double t, double ft, double gt, double tmin, double tmax) {
  const double sign = gt * (iv.gx / std::abs(iv.gx));
  double next;
  if (ft > iv.fx) {
    // Case 1: higher value, the minimum is bracketed between x and t.
    const double cubic = cubicMinimiser(iv.x, iv.fx, iv.gx, t, ft, gt);
    const double quadratic = iv.x + (iv.gx / ((iv.fx - ft) / (t - iv.x) + iv.gx)) / 2.0 * (t - iv.x);
    next = std::abs(cubic - iv.x) < std::abs(quadratic - iv.x) ? cubic : cubic + (quadratic - cubic) / 2.0;
    iv.bracketed = true;
  } else if (sign < 0) {
    // Case 2: derivatives of opposite sign, bracketed.
    const double cubic = cubicMinimiser(t, ft, gt, iv.x, iv.fx, iv.gx);
    const double secant = t + (gt / (gt - iv.gx)) * (iv.x - t);
    next = std::abs(cubic - t) > std::abs(secant - t) ? cubic : secant;
    iv.bracketed = true;
  } else if (std::abs(gt) < std::abs(iv.gx)) {
    // Case 3: same sign, the derivative shrinks; the cubic may have no
    // minimiser beyond t, in which case go to the end of the range.
    const double theta = 3.0 * (iv.fx - ft) / (t - iv.x) + iv.gx + gt;
    const double s = std::max({std::abs(theta), std::abs(iv.gx), std::abs(gt)});
    double gamma = s * std::sqrt(std::max(0.0, (theta / s) * (theta / s) - (iv.gx / s) * (gt / s)));
    if (t > iv.x) gamma = -gamma;
    const double p = (gamma - gt) + theta;
    const double q = (gamma + (iv.gx - gt)) + gamma;
    const double r = p / q;
    double cubic;
    if (r < 0 && gamma != 0)
      cubic = t + r * (iv.x - t);
    else
      cubic = t > iv.x ? tmax : tmin;
    const double secant = t + (gt / (gt - iv.gx)) * (iv.x - t);
    if (iv.bracketed) {
      next = std::abs(cubic - t) < std::abs(secant - t) ? cubic : secant;
      next = t > iv.x ? std::min(t + 0.66 * (iv.y - t), next) : std::max(t + 0.66 * (iv.y - t), next);
    } else {
      next = std::abs(cubic - t) > std::abs(secant - t) ? cubic : secant;
      next = std::clamp(next, tmin, tmax);
    }
  } else {
    // Case 4: same sign, the derivative does not shrink.
    if (iv.bracketed)
      next = cubicMinimiser(t, ft, gt, iv.y, iv.fy, iv.gy);
    else
      next = t > iv.x ? tmax : tmin;
  }
  if (ft > iv.fx) {
    iv.y = t;
    iv.fy = ft;
    iv.gy = gt;
  } else {
    if (sign < 0) {
      iv.y = iv.x;
      iv.fy = iv.fx;
      iv.gy = iv.gx;
    }
    iv.x = t;
    iv.fx = ft;
    iv.gx = gt;
  }
  return next;
}

}  // namespace

LineSearchResult moreThuenteLineSearch(const std::function<double(double, double*)>& phi, double value0,
                                       double derivative0, double initial_step, const LineSearchParameters& params) {
  LineSearchResult best;
  best.value = value0;
  best.derivative = derivative0;
  if (!(derivative0 < 0) || !(params.step_max > params.step_min)) return best;

  const double test = params.ftol * derivative0;
  double width = params.step_max - params.step_min;
  double width_before = 2.0 * width;
  Interval iv{0.0, value0, derivative0, 0.0, value0, derivative0};
  double t = std::clamp(initial_step, params.step_min, params.step_max);
  double lo = 0.0, hi = t + 4.0 * t;
  bool stage_one = true;  // until a step meets sufficient decrease with phi' >= 0

  for (int evaluation = 1; evaluation <= params.max_evaluations; ++evaluation) {
    double g = 0.0;
    const double f = phi(t, &g);
    best.evaluations = evaluation;
    if (std::isfinite(f) && f < best.value) {
      best.step = t;
      best.value = f;
      best.derivative = g;
    }
    const double sufficient = value0 + t * test;
    if (!std::isfinite(f)) {
      // Off the scored region (or overflow): shrink towards the best step.
      t = iv.x + 0.5 * (t - iv.x);
      continue;
    }
    if (f <= sufficient && std::abs(g) <= params.gtol * (-derivative0)) {
      best.step = t;
      best.value = f;
      best.derivative = g;
      best.wolfe = true;
      return best;
    }
    if (stage_one && f <= sufficient && g >= 0) stage_one = false;
    if (iv.bracketed && (t <= lo || t >= hi)) break;               // rounding errors
    if (iv.bracketed && hi - lo <= params.xtol * hi) break;         // interval too small
    if (t == params.step_max && f <= sufficient && g <= test) break;  // the longest step still descends
    if (t == params.step_min && (f > sufficient || g >= test)) break;

    if (stage_one && f <= iv.fx && f > sufficient) {
      // The modified function psi(a) = phi(a) - phi(0) - ftol a phi'(0),
      // whose interval updates keep sufficient decrease in reach (paper, Sec. 3).
      Interval modified{iv.x, iv.fx - iv.x * test, iv.gx - test, iv.y, iv.fy - iv.y * test, iv.gy - test, iv.bracketed};
      const double next = step(modified, t, f - t * test, g - test, lo, hi);
      iv = Interval{modified.x, modified.fx + modified.x * test, modified.gx + test, modified.y,
                    modified.fy + modified.y * test, modified.gy + test, modified.bracketed};
      t = next;
    } else {
      t = step(iv, t, f, g, lo, hi);
    }
    if (iv.bracketed) {
      if (std::abs(iv.y - iv.x) >= 0.66 * width_before) t = iv.x + 0.5 * (iv.y - iv.x);
      width_before = width;
      width = std::abs(iv.y - iv.x);
      lo = std::min(iv.x, iv.y);
      hi = std::max(iv.x, iv.y);
    } else {
      lo = t + 1.1 * (t - iv.x);
      hi = t + 4.0 * (t - iv.x);
    }
    t = std::clamp(t, params.step_min, params.step_max);
    if (iv.bracketed && (t <= lo || t >= hi || hi - lo <= params.xtol * hi)) t = iv.x;
  }
  return best;
}

}  // namespace icrkit::ndt
