// The paper's experiment from Python: the CAD, raw and filtered meshes in,
// the grasp records, Table I, the eligibility and the growth summary out.
// They cross as the JSON the run folder holds (grasps.jsonl lines,
// table1.json, eligibility.json, conservative.json), which the Python layer
// parses into dicts: one definition of every field, exact round trip.

#include <icrkit/eval/conservative_summary.hpp>
#include <icrkit/eval/experiment.hpp>
#include <icrkit/eval/results_tables.hpp>
#include <icrkit/eval/rigid_alignment.hpp>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>

namespace py = pybind11;

namespace icrkit::python {

void bindEvaluation(py::module_& m) {
  m.def(
      "_evaluate",
      [](const TriangleMesh& cad, TriangleMesh raw, TriangleMesh filtered, const std::string& name,
         std::size_t grasps, const std::vector<std::size_t>& fingers, std::uint64_t seed, double alpha, double mu,
         int edges, bool preselection, const std::string& align, const std::vector<double>& conservative,
         std::size_t picks, std::optional<double> patch_radius) {
        eval::ExperimentConfig config;
        config.grasps_per_set = grasps;
        config.finger_counts = fingers;
        config.seed = seed;
        config.alpha = alpha;
        config.friction = mu;
        config.cone_edges = edges;
        config.preselection = preselection;
        config.conservative_sigmas = conservative;
        config.picks_per_grasp = picks;
        if (patch_radius) {
          config.patch = icr::PatchParameters{};
          config.patch->radius_m = *patch_radius;
        }
        if (align != "none" && align != "icp") throw py::value_error("align: expected 'none' or 'icp', got '" + align + "'");
        py::gil_scoped_release release;
        if (align == "icp")
          for (TriangleMesh* mesh : {&raw, &filtered}) eval::transformMesh(*mesh, eval::alignToCad(*mesh, cad).transform);
        const eval::DatasetExperiment experiment({name, &cad, &raw, &filtered}, config);
        const std::vector<eval::GraspRecord> records = experiment.run(0, experiment.itemCount());
        std::vector<std::string> lines;
        for (const eval::GraspRecord& r : records) lines.push_back(eval::toJsonLine(r));
        const std::string table = eval::tableOneJson(eval::computeTableOne(records));
        const std::string eligibility = eval::eligibilityJson(eval::computeEligibility(records));
        const std::string growth = eval::conservativeSummaryJson(eval::computeConservativeSummary(records));
        return std::make_tuple(lines, table, eligibility, growth);
      },
      py::arg("cad"), py::arg("raw"), py::arg("filtered"), py::arg("name"), py::arg("grasps"), py::arg("fingers"),
      py::arg("seed"), py::arg("alpha"), py::arg("mu"), py::arg("edges"), py::arg("preselection"), py::arg("align"),
      py::arg("conservative"), py::arg("picks"), py::arg("patch_radius"));
}

}  // namespace icrkit::python
