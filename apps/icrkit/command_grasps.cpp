// `icrkit grasps MESH --fingers 4 --count 200 --seed 1 -o grasps.jsonl`:
// random force-closure grasps, one JSON object per line.

#include "commands.hpp"
#include "contact_model_options.hpp"

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/icr/grasp_sampling.hpp>
#include <icrkit/icr/graspable_object.hpp>

#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace icrkit::app {
namespace {

struct GraspsOptions {
  GraspMeshOptions mesh;
  ContactModelOptions contact_model;
  std::size_t fingers = 4;
  std::size_t count = 200;
  std::uint64_t seed = 1;
  double min_epsilon = 0.0;
  std::size_t max_attempts = icr::GraspSamplingParameters{}.max_attempts;
  std::string output;
};

std::string graspLines(const std::vector<icr::SampledGrasp>& grasps) {
  std::string text;
  for (const icr::SampledGrasp& grasp : grasps)
    text += nlohmann::json{{"contacts", grasp.contacts}, {"epsilon", grasp.epsilon}}.dump() + "\n";
  return text;
}

void run(const GraspsOptions& options, CommandContext& context) {
  const double read_start = context.elapsedMs();
  const GraspMesh input = loadGraspMesh(options.mesh, context);
  const double read_ms = context.elapsedMs() - read_start;

  const icr::ContactModel model = options.contact_model.model();
  icr::GraspSamplingParameters params;
  params.fingers = options.fingers;
  params.count = options.count;
  params.seed = options.seed;
  params.min_epsilon = options.min_epsilon;
  params.max_attempts = options.max_attempts;
  icr::GraspSamplingStatistics statistics;
  std::vector<icr::SampledGrasp> grasps;
  std::size_t unreferenced = 0;
  try {
    const icr::GraspableObject object =
        icr::GraspableObject::withDefaultFrame(input.mesh, input.excluded, options.mesh.torque_reference);
    unreferenced = object.unreferencedCount();
    grasps = icr::sampleForceClosureGrasps(object, model, params, &statistics);
  } catch (const InputError& error) {
    throw namingMesh(options.mesh.path, error);
  }
  if (grasps.size() < options.count)
    context.note("icrkit: " + options.mesh.path + ": found " + std::to_string(grasps.size()) + " of " +
                 std::to_string(options.count) + " grasps in " + std::to_string(statistics.attempts) +
                 " attempts (raise --max-attempts or lower --min-epsilon)");

  const std::string lines = graspLines(grasps);
  if (!options.output.empty())
    writeFileAtomically(options.output, [&lines](std::ostream& out) { out << lines; }, false);

  nlohmann::json summary{
      {"mesh", options.mesh.path},
      {"output", options.output.empty() ? nlohmann::json(nullptr) : nlohmann::json(options.output)},
      {"fingers", options.fingers},
      {"count", grasps.size()},
      {"requested", options.count},
      {"seed", options.seed},
      {"min_epsilon", options.min_epsilon},
      {"max_attempts", options.max_attempts},
      {"attempts", statistics.attempts},
      {"rejected_by_precheck", statistics.rejected_by_precheck},
      {"hulls_built", statistics.hulls_built},
      {"grasps_per_second",
       statistics.time_ms > 0 ? static_cast<double>(grasps.size()) / (statistics.time_ms / 1000.0) : 0.0},
      {"model", nlohmann::json::parse(icr::contactModelJson(model))},
      {"time_ms", {{"read", read_ms}, {"sampling", statistics.time_ms}, {"total", context.elapsedMs()}}}};
  summary.update(graspMeshJson(input, options.mesh, unreferenced));

  if (options.output.empty()) {
    // Without -o the grasps still have to reach the user without breaking
    // "one JSON object on stdout": inside the summary with --json, else as
    // JSON lines on stdout with the summary on stderr.
    if (context.options().json) {
      nlohmann::json list = nlohmann::json::array();
      for (const icr::SampledGrasp& grasp : grasps) list.push_back({{"contacts", grasp.contacts}, {"epsilon", grasp.epsilon}});
      summary["grasps"] = list;
      context.emit(summary);
    } else {
      std::cout << lines << std::flush;
      context.note("grasps: " + std::to_string(grasps.size()) + " in " + std::to_string(statistics.attempts) +
                   " attempts (" + std::to_string(statistics.rejected_by_precheck) + " rejected by the pre-check, " +
                   std::to_string(statistics.hulls_built) + " hulls), " + std::to_string(statistics.time_ms) + " ms");
    }
    return;
  }
  context.emit(summary);
}

}  // namespace

void addGraspsCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "grasps",
      "Random force-closure grasps (deterministic for a seed, whatever --threads). Writes one JSON object per line, "
      "{\"contacts\": [...], \"epsilon\": e}, to -o, or to stdout without -o (inside the summary with --json)");
  auto options = std::make_shared<GraspsOptions>();
  options->mesh.addTo(*command);
  options->contact_model.addTo(*command);
  command->add_option("--fingers", options->fingers, "Contacts per grasp")->check(atLeast(2))->capture_default_str();
  command->add_option("--count", options->count, "Grasps wanted")->check(atLeast(1))->capture_default_str();
  command->add_option("--seed", options->seed, "Random seed")->check(CLI::NonNegativeNumber)->capture_default_str();
  command->add_option("--min-epsilon", options->min_epsilon, "Keep only grasps whose epsilon is at least this")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  command->add_option("--max-attempts", options->max_attempts, "Give up after this many random draws")
      ->check(atLeast(1))
      ->capture_default_str();
  command->add_option("-o,--output", options->output, "Output .jsonl, written atomically");
  command->callback([&runner, options] { runner = [options](CommandContext& context) { run(*options, context); }; });
}

}  // namespace icrkit::app
