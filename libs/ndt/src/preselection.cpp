#include <icrkit/core/error.hpp>
#include <icrkit/ndt/preselection.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace icrkit::ndt {

const char* preselectionRuleName(PreselectionRule rule) {
  switch (rule) {
    case PreselectionRule::Robust: return "default";
    case PreselectionRule::PaperMean: return "paper-mean";
    case PreselectionRule::None: return "none";
  }
  return "default";
}

PreselectionRule parsePreselectionRule(const std::string& name, const std::string& source) {
  if (name == "default" || name == "robust") return PreselectionRule::Robust;
  if (name == "paper-mean" || name == "paper") return PreselectionRule::PaperMean;
  if (name == "none") return PreselectionRule::None;
  throw InputError(source, "", "unknown preselection rule '" + name + "', expected default, paper-mean or none");
}

std::vector<PreselectionRule> allPreselectionRules() {
  return {PreselectionRule::Robust, PreselectionRule::PaperMean, PreselectionRule::None};
}

namespace {

// The value at which the running weight (in value order, ties by index)
// first reaches half the total.
double weightedMedianOf(const std::vector<double>& values, const std::vector<double>& weights) {
  if (values.empty()) return 0.0;
  std::vector<std::size_t> order(values.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return values[a] < values[b] || (values[a] == values[b] && a < b);
  });
  double total = 0;
  for (const double w : weights) total += w;
  double running = 0;
  for (const std::size_t i : order) {
    running += weights[i];
    if (running >= 0.5 * total) return values[i];
  }
  return values[order.back()];
}

void validate(const std::vector<double>& cardinality, const std::vector<double>& flatness,
              const PreselectionParameters& p) {
  if (cardinality.size() != flatness.size())
    throw InputError("preselection", "", "cardinality and flatness must have one value per point, got " +
                                             std::to_string(cardinality.size()) + " and " +
                                             std::to_string(flatness.size()));
  for (std::size_t i = 0; i < cardinality.size(); ++i)
    if (!(std::isfinite(cardinality[i]) && cardinality[i] >= 0 && std::isfinite(flatness[i]) && flatness[i] >= 0))
      throw InputError("preselection", "point " + std::to_string(i),
                       "expected a finite cardinality and flatness >= 0, got " + std::to_string(cardinality[i]) +
                           " and " + std::to_string(flatness[i]));
  p.validate();
}

}  // namespace

void PreselectionParameters::validate() const {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  if (!(positive(robust_k) && positive(min_log_flatness_spread) && positive(always_flat) &&
        std::isfinite(min_cardinality) && min_cardinality >= 0 && boundary_fraction >= 0 && boundary_fraction <= 1))
    throw InputError("PreselectionParameters", "",
                     "the default rule's parameters must be positive (boundary fraction in [0, 1])");
  const auto check = [](const char* field, const std::optional<double>& t) {
    if (t && !(std::isfinite(*t) && *t >= 0)) {
      std::ostringstream text;
      text << "expected a finite threshold >= 0, got " << *t;
      throw InputError(field, "", text.str());
    }
  };
  check("PreselectionParameters::cardinality_threshold", cardinality_threshold);
  check("PreselectionParameters::flatness_threshold", flatness_threshold);
}

Preselection preselect(const std::vector<double>& cardinality, const std::vector<double>& flatness,
                       const PreselectionParameters& params) {
  validate(cardinality, flatness, params);
  Preselection out;
  PreselectionReport& s = out.summary;
  const std::size_t n = cardinality.size();
  s.rule = params.rule;
  s.points = n;
  out.excluded.assign(n, 0);
  if (n == 0) return out;

  double cardinality_sum = 0, flatness_sum = 0;
  // Flatness statistics per unit of surface, not per sample: a point stands
  // for about 1 / |W_s| of its window's area. A fused recording is many
  // times denser where many views overlap (and the noise is averaged)
  // than where few saw it, and per sample its dense parts would set the
  // noise level that its sparse, noisier parts are then measured against
  // (on the real bunny: 2 % of the points excluded, but 9.5 % of the
  // vertices grasps land on).
  std::vector<double> log_flatness, weight;
  log_flatness.reserve(n);
  weight.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    cardinality_sum += cardinality[i];
    flatness_sum += flatness[i];
    if (flatness[i] > 0) {
      log_flatness.push_back(std::log(flatness[i]));
      weight.push_back(1.0 / std::max(cardinality[i], 1.0));
    }
  }
  s.mean_cardinality = cardinality_sum / static_cast<double>(n);
  s.mean_flatness = flatness_sum / static_cast<double>(n);
  std::vector<double> area_weight(n);
  for (std::size_t i = 0; i < n; ++i) area_weight[i] = 1.0 / std::max(cardinality[i], 1.0);
  s.median_cardinality = weightedMedianOf(cardinality, area_weight);
  const double log_median = weightedMedianOf(log_flatness, weight);
  s.median_flatness = log_flatness.empty() ? 0.0 : std::exp(log_median);
  std::vector<double> deviation(log_flatness.size());
  for (std::size_t i = 0; i < deviation.size(); ++i) deviation[i] = std::abs(log_flatness[i] - log_median);
  s.log_flatness_spread = 1.4826 * weightedMedianOf(deviation, weight);
  if (params.rule == PreselectionRule::None) return out;

  if (params.rule == PreselectionRule::PaperMean) {
    s.cardinality_threshold = s.mean_cardinality;
    s.flatness_threshold = s.mean_flatness;
  } else {
    const double k = params.robust_k;
    const double spread = std::max(s.log_flatness_spread, params.min_log_flatness_spread);
    s.flatness_threshold = log_flatness.empty() ? params.always_flat
                                                : std::min(params.always_flat, std::exp(log_median - k * spread));
    std::vector<double> deviation(n);
    for (std::size_t i = 0; i < n; ++i) deviation[i] = std::abs(cardinality[i] - s.median_cardinality);
    const double cardinality_spread = 1.4826 * weightedMedianOf(deviation, area_weight);
    s.cardinality_threshold =
        std::max(params.min_cardinality, std::min(params.boundary_fraction * s.median_cardinality,
                                                  s.median_cardinality - k * cardinality_spread));
  }
  if (params.cardinality_threshold) s.cardinality_threshold = *params.cardinality_threshold;
  if (params.flatness_threshold) s.flatness_threshold = *params.flatness_threshold;

  for (std::size_t i = 0; i < n; ++i) {
    const bool sparse = cardinality[i] < s.cardinality_threshold;
    // A window of flatness 0 is a line or a point: never a surface to trust.
    const bool rough = flatness[i] < s.flatness_threshold || flatness[i] == 0.0;
    out.excluded[i] = (sparse || rough) ? 1 : 0;
    if (sparse && rough)
      ++s.excluded_both;
    else if (sparse)
      ++s.excluded_cardinality_only;
    else if (rough)
      ++s.excluded_flatness_only;
  }
  s.excluded = s.excluded_both + s.excluded_cardinality_only + s.excluded_flatness_only;
  return out;
}

PreselectionReport applyPreselection(AttributeSet& attributes, std::size_t count, const PreselectionParameters& params,
                                     const std::string& source) {
  const auto column = [&](const char* name) -> const std::vector<double>& {
    const Attribute* a = attributes.find(name);
    if (!a)
      throw InputError(source, "",
                       std::string("no '") + name +
                           "' attribute: preselection needs the smoothing layer's cardinality and flatness "
                           "(a filtered cloud or mesh written by icrkit smooth or icrkit reconstruct)");
    if (a->values.size() != count)
      throw InputError(source, "", std::string("the '") + name + "' attribute has " +
                                       std::to_string(a->values.size()) + " values, expected " + std::to_string(count));
    return a->values;
  };
  Preselection result;
  try {
    result = preselect(column("cardinality"), column("flatness"), params);
  } catch (const InputError& e) {
    if (e.source() != "preselection") throw;
    throw InputError(source, e.location(), e.detail());
  }
  std::vector<double> flags(result.excluded.begin(), result.excluded.end());
  attributes.add("excluded", ScalarType::UInt8, std::move(flags));
  return result.summary;
}

}  // namespace icrkit::ndt
