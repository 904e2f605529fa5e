#include "conservative_options.hpp"

#include "argument_parsing.hpp"

#include <icrkit/core/error.hpp>

namespace icrkit::app {

void ConservativeOptions::addTo(CLI::App& command) {
  command
      .add_option_function<std::string>(
          "--conservative", [this](const std::string& value) { sigmas = value; },
          "Uncertainty-aware regions: a vertex joins only if the grasp holds for every normal within K x its "
          "normal_sigma and every position within K x its position_sigma (vertex attributes written by smooth, "
          "reconstruct and mesh). K is optional, default 1; write --conservative=K before a positional argument")
      ->expected(0, 1);
  command.add_option("--normal-uncertainty", normal_angle,
                     "Conservative growth with this fixed normal bound (radians) instead of K x normal_sigma: for "
                     "meshes without the attribute, or a known sensor accuracy");
  command.add_option("--position-uncertainty", position_offset,
                     "Conservative growth with this fixed position bound (metres) instead of K x position_sigma");
}

std::optional<icr::ConservativeGrowth> ConservativeOptions::growth() const {
  if (!sigmas && !normal_angle && !position_offset) return std::nullopt;
  icr::ConservativeGrowth growth;
  if (sigmas && !sigmas->empty()) {
    double k = 0.0;
    if (!parseNumber(*sigmas, k))
      throw InputError("--conservative", "",
                       "expected K, a number >= 0, got '" + *sigmas + "' (write --conservative=K before a positional argument)");
    growth.sigmas = k;
  }
  growth.normal_angle = normal_angle;
  growth.position_offset = position_offset;
  try {
    growth.validate();
  } catch (const InputError& error) {
    throw InputError("--conservative", "", error.detail());
  }
  return growth;
}

nlohmann::json conservativeJson(const std::optional<icr::ConservativeGrowth>& growth) {
  if (!growth) return nullptr;
  return {{"sigmas", growth->sigmas},
          {"normal_uncertainty_rad", growth->normal_angle ? nlohmann::json(*growth->normal_angle) : nlohmann::json(nullptr)},
          {"position_uncertainty_m",
           growth->position_offset ? nlohmann::json(*growth->position_offset) : nlohmann::json(nullptr)}};
}

}  // namespace icrkit::app
