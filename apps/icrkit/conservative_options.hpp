#pragma once
// --conservative [K], --normal-uncertainty, --position-uncertainty: the
// uncertainty-aware region growth (icr/conservative_growth.hpp), shared by
// the commands that grow regions (icr, evaluate, paper, sensitivity).

#include <icrkit/icr/conservative_growth.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace icrkit::app {

struct ConservativeOptions {
  std::optional<std::string> sigmas;  ///< as given; "" for a bare --conservative
  std::optional<double> normal_angle;
  std::optional<double> position_offset;

  void addTo(CLI::App& command);
  /// Unset unless one of the options was given. InputError (exit 2) for a K
  /// that is not a number >= 0 or a negative bound.
  std::optional<icr::ConservativeGrowth> growth() const;
};

/// {"sigmas": K, "normal_uncertainty_rad": a or null, "position_uncertainty_m": d or null},
/// or null for plain growth.
nlohmann::json conservativeJson(const std::optional<icr::ConservativeGrowth>& growth);

}  // namespace icrkit::app
