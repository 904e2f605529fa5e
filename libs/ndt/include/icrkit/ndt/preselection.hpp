#pragma once
/// \file
/// Point preselection (Section III-B.2 of Krug et al.): which points of a
/// smoothed cloud are too uncertain to join an ICR. It reads the two
/// criteria the smoothing layer records per point, the window cardinality
/// |W_s| and the flatness F = sqrt(l2 / l3), and decides by one of three
/// rules (docs/smoothing.md, "Preselection rules"):
///
/// - `paper-mean`, the paper's words taken literally: excluded when |W_s| or
///   F is below its mean over the cloud. Two "below the mean" tests pass
///   about a quarter of any real cloud (76 % of the laser scan bun000 is
///   excluded), so grasps almost never land on four kept vertices.
/// - `default` (robust), what the paper means: exclude isolated points and
///   windows that are not flat *relative to the noise actually present*.
///   The noise sets the typical flatness of the cloud (F ~ r / (2 sigma) on
///   a plane), so the flatness test is relative to the median of ln F and
///   its spread (MAD): F < median(F) exp(-k sigma_ln F), both weighted by
///   the surface each point stands for (1 / |W_s|: a fused recording is
///   densest where most views overlap). ln F, not F: the
///   noise scales F, and a scan's range-dependent noise makes F spread over
///   a factor, not an offset. A window flatter than `always_flat` is never
///   excluded (a clean cloud has no noise to be relative to). Isolated
///   points: fewer than `min_cardinality` points, or fewer than both
///   `boundary_fraction` of the median and median - k sigma (a point at the
///   border of a surface sees half a window: that is not isolated), median
///   and spread weighted alike.
/// - `none`: nothing is excluded.
///
/// Statistics are over all points (in index order: the same bits for any
/// thread count); a point with F = 0 (its window is a line or a point) is
/// left out of the flatness statistics and always excluded.

#include <icrkit/core/attributes.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::ndt {

enum class PreselectionRule { Robust, PaperMean, None };

/// "default", "paper-mean", "none".
const char* preselectionRuleName(PreselectionRule rule);
/// Parses those names (and "robust" for "default"); InputError naming
/// `source` otherwise.
PreselectionRule parsePreselectionRule(const std::string& name,
                                       const std::string& source = "PreselectionParameters::rule");
/// The rules in the order reports list them: default, paper-mean, none.
std::vector<PreselectionRule> allPreselectionRules();

struct PreselectionParameters {
  PreselectionRule rule = PreselectionRule::Robust;
  /// Explicit thresholds replace the rule's own (paper-mean or default):
  /// excluded when cardinality < `cardinality_threshold` or flatness <
  /// `flatness_threshold`.
  std::optional<double> cardinality_threshold;
  std::optional<double> flatness_threshold;

  // The default rule.
  /// Robust standard deviations (1.4826 MAD) below the median.
  double robust_k = 3.0;
  /// Floor of the spread of ln F (a cloud whose flatness hardly varies
  /// would otherwise exclude half of itself).
  double min_log_flatness_spread = 0.05;
  /// Windows at least this flat are kept whatever the cloud: F = 4 is a
  /// thickness of r / 8, or a curvature radius of about 1.2 r on a clean
  /// sample. Higher values exclude gently curved clean surface (at 10, a
  /// clean sample of the bottle lost 2/3 of its eligible grasps).
  double always_flat = 4.0;
  /// A window of fewer points is isolated: no plane to trust.
  double min_cardinality = 6.0;
  /// The cardinality threshold never exceeds this fraction of the median.
  double boundary_fraction = 0.5;

  /// Throws InputError naming the field ("PreselectionParameters::flatness_threshold",
  /// ...) for an explicit threshold that is not finite and >= 0 or a default
  /// rule parameter out of range. preselect() calls it first.
  void validate() const;
};

struct PreselectionReport {
  PreselectionRule rule = PreselectionRule::Robust;
  std::size_t points = 0;
  double mean_cardinality = 0.0;
  double mean_flatness = 0.0;
  double median_cardinality = 0.0;  ///< weighted by 1 / |W_s|
  double median_flatness = 0.0;  ///< exp(median ln F) over F > 0, weighted by 1 / |W_s|
  double log_flatness_spread = 0.0;  ///< 1.4826 MAD of ln F, weighted alike (before the floor)
  /// The thresholds applied; 0 with rule none.
  double cardinality_threshold = 0.0;
  double flatness_threshold = 0.0;
  std::size_t excluded = 0;
  std::size_t excluded_cardinality_only = 0;
  std::size_t excluded_flatness_only = 0;
  std::size_t excluded_both = 0;
};

struct Preselection {
  std::vector<std::uint8_t> excluded;  ///< one 0/1 flag per point
  PreselectionReport summary;
};

/// Decides every point from its cardinality and flatness (equal lengths;
/// InputError otherwise or when a value is negative or not finite).
Preselection preselect(const std::vector<double>& cardinality, const std::vector<double>& flatness,
                       const PreselectionParameters& params = {});

/// Reads the `cardinality` and `flatness` attributes of `count` elements
/// (a smoothed cloud, or a mesh whose vertices are one) and writes the
/// `excluded` flags (uchar); with rule none the flags are all 0. InputError
/// naming `source` when an attribute is missing or has the wrong length.
PreselectionReport applyPreselection(AttributeSet& attributes, std::size_t count, const PreselectionParameters& params,
                                     const std::string& source);

}  // namespace icrkit::ndt
