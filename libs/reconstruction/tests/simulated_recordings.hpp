#pragma once
/// \file
/// Simulated recordings for the reader, filter and fusion tests, made once
/// per test process through icrkit::sim (linked to the tests only).

#include <icrkit/sim/dataset.hpp>

#include <filesystem>
#include <map>
#include <string>
#include <system_error>
#include <unistd.h>

namespace icrkit::reconstruction::testing_support {

/// A Kinect/setup B recording of the cup; `perfect`: reported poses are the true ones.
inline std::string simulatedRecording(int views, bool perfect) {
  // Removed when the test process ends.
  struct Made : std::map<std::pair<int, bool>, std::string> {
    ~Made() {
      std::error_code error;
      for (const auto& entry : *this) std::filesystem::remove_all(entry.second, error);
    }
  };
  static Made made;
  const auto key = std::make_pair(views, perfect);
  auto it = made.find(key);
  if (it != made.end()) return it->second;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("icrkit_scanio_" + std::to_string(::getpid()) + "_" + std::to_string(views) +
                                     (perfect ? "_perfect" : "_noisy"));
  sim::DatasetSpec spec;
  spec.object = "cup";
  spec.sensor = sim::SensorType::Kinect;
  spec.acquisition.setup = sim::Setup::B;
  spec.acquisition.views = views;
  if (perfect) spec.acquisition.errors = sim::perfectPoses();
  sim::simulateDataset(spec, dir.string());
  made[key] = dir.string();
  return dir.string();
}

/// A fresh scratch folder (removed by the caller).
inline std::filesystem::path scratchFolder(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("icrkit_scanio_" + std::to_string(::getpid()) + "_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace icrkit::reconstruction::testing_support
