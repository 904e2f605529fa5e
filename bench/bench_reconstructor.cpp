// The incremental Reconstructor against the file path, one process each
// (peak memory is per process):
//
//   bench_reconstructor feed INPUT [--meshes 0|1]   each scan read and
//       unprojected (the driver's work, not timed) and add()ed as it comes,
//       then update(): prints the add time per scan, the time from the last
//       scan to the meshes, and peak RSS as one JSON line.
//   bench_reconstructor file INPUT [--meshes 0|1]   reconstructRawlog(INPUT):
//       total time and peak RSS as one JSON line.
//
// INPUT: a rawlog or a TUM folder (with --intrinsics fx,fy,cx,cy
// --depth-scale S --poses FILE as for `icrkit reconstruct`).
// docs/performance.md records the runs.

#include <icrkit/core/error.hpp>
#include <icrkit/reconstruction/input/scan_source.hpp>
#include <icrkit/reconstruction/reconstruction_pipeline.hpp>
#include <icrkit/reconstruction/reconstructor.hpp>

#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// User and system time of the whole process (every thread), seconds.
double cpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

double peakMegabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // kilobytes on Linux
}

// The registration's per-scan part, done by add(): the scan against the
// model so far (scan_to_model) and, registering as the scans arrive, its
// alignment and first pairs.
double perScanRegistrationMs(const icrkit::reconstruction::ReconstructionResult& r) {
  double ms = 0.0;
  for (const auto& scan : r.registration.scans) ms += scan.time_ms;
  return ms;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace icrkit::reconstruction;
  if (argc < 3) {
    std::fprintf(stderr, "usage: bench_reconstructor feed|file INPUT [--meshes 0|1] [--raw-mesh 0|1] [--incremental 0|1] [--intrinsics fx,fy,cx,cy] "
                         "[--depth-scale S] [--poses FILE]\n");
    return 2;
  }
  const std::string mode = argv[1], input = argv[2];
  ReconstructionParameters params;
  for (int i = 3; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--meshes") {
      params.make_meshes = value != "0";
    } else if (key == "--raw-mesh") {
      params.make_raw_mesh = value != "0";
    } else if (key == "--incremental") {
      params.registration.incremental = value != "0";
    } else if (key == "--poses") {
      params.pose_file = value;
    } else if (key == "--depth-scale") {
      params.depth_camera.depth_scale = std::stod(value);
    } else if (key == "--intrinsics") {
      icrkit::CameraIntrinsics k;
      char comma;
      std::istringstream in(value);
      in >> k.fx >> comma >> k.fy >> comma >> k.cx >> comma >> k.cy;
      params.depth_camera.intrinsics = k;
    } else {
      std::fprintf(stderr, "unknown option %s\n", key.c_str());
      return 2;
    }
  }
  try {
    if (mode == "file") {
      const auto start = Clock::now();
      const ReconstructionResult r = reconstructRawlog(input, params);
      std::printf("{\"mode\": \"file\", \"scans\": %zu, \"total_s\": %.3f, \"peak_mb\": %.1f, \"faces\": %zu}\n",
                  r.poses.size(), secondsSince(start), peakMegabytes(), r.filtered_mesh.faces.size());
      return 0;
    }
    ScanReaderOptions options;
    options.pose_file = params.pose_file;
    options.depth_camera = params.depth_camera;
    ScanReader reader(input, options);  // the driver: one frame at a time
    Reconstructor reconstructor(params, input);
    double add_s = 0.0;
    while (auto scan = reader.next()) {
      const auto added = Clock::now();
      reconstructor.add(std::move(*scan));
      add_s += secondsSince(added);
    }
    const auto start = Clock::now();
    const double cpu_before = cpuSeconds();
    const ReconstructionResult& r = reconstructor.update();
    const double update_s = secondsSince(start);
    const double update_cpu_s = cpuSeconds() - cpu_before;
    std::printf("{\"mode\": \"feed\", \"scans\": %zu, \"add_s_per_scan\": %.4f, \"after_last_scan_s\": %.3f, \"after_last_scan_cpu_s\": %.3f, "
                "\"stored_mb\": %.1f, \"peak_mb\": %.1f, \"faces\": %zu, \"stages_s\": {\"per_scan_registration\": %.3f, "
                "\"registration\": %.3f, \"fusion\": %.3f, \"normals\": %.3f, \"raw_mesh\": %.3f, \"smoothing\": %.3f, "
                "\"filtered_mesh\": %.3f}}\n",
                r.poses.size(), add_s / static_cast<double>(r.poses.size()), update_s, update_cpu_s,
                reconstructor.storedBytes() / 1048576.0, peakMegabytes(), r.filtered_mesh.faces.size(),
                perScanRegistrationMs(r) / 1e3, r.times.registration_ms / 1e3, r.times.fusion_ms / 1e3, r.times.normals_ms / 1e3,
                r.times.raw_mesh_ms / 1e3, r.times.smoothing_ms / 1e3, r.times.filtered_mesh_ms / 1e3);
    return 0;
  } catch (const icrkit::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
