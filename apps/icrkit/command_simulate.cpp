// `icrkit simulate`: one simulated recording (sim::simulateDataset) of a CAD
// object or a user mesh with a sensor model and an acquisition setup.
// `icrkit datasets list|make`: the paper's nine object/sensor pairs.

#include "argument_parsing.hpp"
#include "commands.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/sim/cad_objects.hpp>
#include <icrkit/sim/dataset.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace icrkit::app {
namespace {

struct SimulateOptions {
  std::string object = "cup";
  std::string mesh;
  std::string sensor = "kinect";
  std::string setup;
  int views = 36;
  std::uint64_t seed = 1;
  double distance = 0.0;
  bool perfect_poses = false;
  std::string pose_error = "arm";
  std::string correlated_noise;
  std::string output;
};

// --correlated-noise SHARE[,PIXELS]: the Kinect's shared depth noise. The
// ranges are the library's to check (simulateDataset names them).
void parseCorrelatedNoise(const std::string& text, sim::DatasetSpec& spec) {
  if (text.empty()) return;
  const std::vector<std::string> parts = split(text, ',');
  const bool numbers = (parts.size() == 1 || parts.size() == 2) && parseNumber(parts[0], spec.correlated_noise_share) &&
                       (parts.size() == 1 || parseNumber(parts[1], spec.correlated_noise_length_px));
  if (!numbers) throw InputError("--correlated-noise", "", "expected SHARE[,PIXELS] (e.g. 0.75,3), got '" + text + "'");
}

// The text every --pose-error takes; documented once for both commands.
constexpr const char* kPoseErrorHelp =
    "Robot-reported pose errors: arm (industrial arm: 0.3 mm / 0.03 deg per view, a fixed hand-eye offset and drift), "
    "mobile (mobile manipulator: 3 mm / 0.5 deg per axis, independent per view), none, or per-view sigmas T,R "
    "with units, e.g. 5mm,1deg (docs/rawlog.md)";

nlohmann::json simulate(const SimulateOptions& o, CommandContext& context) {
  sim::DatasetSpec spec;
  spec.sensor = sim::parseSensorType(o.sensor);
  // The paper pairs the SR4000 with setup A and the Kinect with setup B.
  spec.acquisition.setup =
      o.setup.empty() ? (spec.sensor == sim::SensorType::Sr4000 ? sim::Setup::A : sim::Setup::B) : sim::parseSetup(o.setup);
  if (o.mesh.empty()) {
    sim::parseCadObject(o.object);  // fails before any work
    spec.object = o.object;
  } else {
    spec.mesh_path = o.mesh;
  }
  spec.acquisition.views = o.views;
  spec.acquisition.seed = o.seed;
  if (o.distance != 0.0) spec.acquisition.distance = o.distance;  // 0: the setup's default
  spec.acquisition.errors = o.perfect_poses ? sim::perfectPoses() : sim::parsePoseErrorModel(o.pose_error);
  parseCorrelatedNoise(o.correlated_noise, spec);
  const sim::SimulationReport s = renamingInputErrors(
      "correlated noise", "--correlated-noise", [&] { return sim::simulateDataset(spec, o.output, context.progress()); });
  return nlohmann::json::parse(sim::datasetRecordJson(spec, s));
}

struct DatasetsOptions {
  std::string output = "datasets/generated";
  std::string only;
  std::string pose_error = "arm";
};

nlohmann::json makeDatasets(const DatasetsOptions& o, CommandContext& context) {
  const sim::PoseErrorModel errors = sim::parsePoseErrorModel(o.pose_error);
  std::vector<sim::DatasetSpec> specs = sim::paperDatasets(split(o.only, ','));  // none named: all nine
  nlohmann::json made = nlohmann::json::array();
  for (sim::DatasetSpec& spec : specs) {
    spec.acquisition.errors = errors;
    const std::string directory =
        (std::filesystem::path(o.output) / sim::datasetFolderName(spec, o.pose_error)).string();
    context.note("simulating " + sim::datasetName(spec) + " -> " + directory);
    made.push_back(
        nlohmann::json::parse(sim::datasetRecordJson(spec, sim::simulateDataset(spec, directory, context.progress()))));
  }
  return {{"output", o.output},
          {"pose_error", errors.name},
          {"datasets", made},
          {"time_ms", {{"total", context.elapsedMs()}}}};
}

}  // namespace

void addSimulateCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "simulate",
      "Simulated range scans of an object (the paper's CAD objects or any mesh) with a Kinect or SwissRanger "
      "SR4000 model in the paper's setup A (SR4000 on an arm around the object) or B (fixed Kinect, object turned "
      "on the flange). Writes DIR/scans.rawlog (MRPT, gzip), ground_truth.txt and reported_poses.txt (TUM), "
      "object.ply, scene.ply and manifest.json; see docs/rawlog.md");
  auto o = std::make_shared<SimulateOptions>();
  command->add_option("--object", o->object, "cup, paper_cup, bottle, coffee_pot, wooden_toy_1, wooden_toy_2")
      ->capture_default_str();
  command->add_option("--mesh", o->mesh, "Scan this mesh (.ply/.obj, metres, standing on z = 0) instead of --object");
  command->add_option("--sensor", o->sensor, "kinect or sr4000")->capture_default_str();
  command->add_option("--setup", o->setup, "A or B (default: A for sr4000, B for kinect, as in the paper)");
  command->add_option("--views", o->views, "Number of views")->capture_default_str();
  command->add_option("--seed", o->seed, "Seed of every random choice (noise, pose errors)")->capture_default_str();
  command->add_option("--distance", o->distance, "Camera distance to the object's centre in metres (0: the setup's)");
  auto* perfect = command->add_flag("--perfect-poses", o->perfect_poses,
                                    "Report the true camera poses (same as --pose-error none)");
  command->add_option("--pose-error", o->pose_error, kPoseErrorHelp)->capture_default_str()->excludes(perfect);
  command->add_option("--correlated-noise", o->correlated_noise,
                      "Kinect: SHARE[,PIXELS] of the depth noise's variance that neighbouring pixels share (a "
                      "Gaussian random field of that length, default 3 px; the rest stays independent per pixel, "
                      "the total sigma unchanged). Default: 0, all independent (docs/sensors.md, \"Correlated depth "
                      "noise\")");
  command->add_option("-o,--output", o->output, "Output folder (replaced only if it holds an earlier simulation)")
      ->required();
  command->callback([&runner, o] {
    runner = [o](CommandContext& context) {
      context.mapFields({{"AcquisitionParameters::views", "--views"},
                         {"AcquisitionParameters::distance", "--distance"},
                         {"pose error model", "--pose-error"},
                         {"sensor name", "--sensor"},
                         {"setup name", "--setup"},
                         {"object name", "--object"}});
      context.emit(simulate(*o, context));
    };
  });
}

void addDatasetsCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand("datasets", "The paper's nine simulated datasets (datasets/paper_datasets.json)");
  command->require_subcommand(1);
  auto* list = command->add_subcommand("list", "The nine object/sensor pairs and their settings");
  list->callback([&runner] {
    runner = [](CommandContext& context) { context.emit(nlohmann::json::parse(sim::paperDatasetsJson())); };
  });
  auto* make = command->add_subcommand(
      "make", "Simulate all of them (or --only some) into OUTPUT/NAME (OUTPUT/NAME_MODEL under another --pose-error "
              "than arm, e.g. cup_kinect_B_mobile, cup_kinect_B_5mm_1deg)");
  auto o = std::make_shared<DatasetsOptions>();
  make->add_option("-o,--output", o->output, "Output folder (git-ignored by default)")->capture_default_str();
  make->add_option("--only", o->only, "Comma-separated dataset names (see `icrkit datasets list`)");
  make->add_option("--pose-error", o->pose_error, kPoseErrorHelp)->capture_default_str();
  make->callback([&runner, o] {
    runner = [o](CommandContext& context) {
      context.mapFields({{"pose error model", "--pose-error"}, {"dataset names", "--only"}});
      context.emit(makeDatasets(*o, context));
    };
  });
}

}  // namespace icrkit::app
