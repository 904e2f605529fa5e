#pragma once
/// \file
/// The sensitivity study's table (eval::SensitivityTable) as Markdown and as
/// a three-panel plot, and the writer of DIR/sensitivity.{md,json,svg,png}.

#include <icrkit/eval/sensitivity_study.hpp>

#include <string>
#include <vector>

namespace icrkit::report {

std::string sensitivityMarkdown(const eval::SensitivityTable& table);
/// Three panels (eligibility, Int, FP against noise), the raw mesh in black,
/// one coloured line per rule for the filtered meshes.
std::string sensitivitySvg(const eval::SensitivityTable& table);
std::vector<unsigned char> sensitivityPng(const eval::SensitivityTable& table);

/// DIR/sensitivity.{md,json,svg,png}; returns the paths.
std::vector<std::string> writeSensitivityOutputs(const std::string& directory, const eval::SensitivityTable& table);

}  // namespace icrkit::report
