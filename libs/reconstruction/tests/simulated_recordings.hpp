#pragma once
/// \file
/// Simulated recordings for the reader, filter and fusion tests, made once
/// per test process through icrkit::sim (linked to the tests only).

#include <icrkit/sim/dataset.hpp>

#include <filesystem>
#include <map>
#include <tuple>
#include <string>
#include <system_error>
#include <unistd.h>

namespace icrkit::reconstruction::testing_support {

/// A recording of a CAD object (the cup by default) with the Kinect in
/// setup B or the SR4000 in setup A; `perfect`: reported poses are the
/// true ones.
inline std::string simulatedRecording(int views, bool perfect, sim::SensorType sensor = sim::SensorType::Kinect,
                                      const std::string& object = "cup") {
  // Removed when the test process ends.
  struct Made : std::map<std::tuple<int, bool, int, std::string>, std::string> {
    ~Made() {
      std::error_code error;
      for (const auto& entry : *this) std::filesystem::remove_all(entry.second, error);
    }
  };
  static Made made;
  const auto key = std::make_tuple(views, perfect, static_cast<int>(sensor), object);
  auto it = made.find(key);
  if (it != made.end()) return it->second;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("icrkit_scanio_" + std::to_string(::getpid()) + "_" + std::to_string(views) +
                                     (perfect ? "_perfect" : "_noisy") + "_" + sim::sensorTypeName(sensor) + "_" + object);
  sim::DatasetSpec spec;
  spec.object = object;
  spec.sensor = sensor;
  spec.acquisition.setup = sensor == sim::SensorType::Kinect ? sim::Setup::B : sim::Setup::A;
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
