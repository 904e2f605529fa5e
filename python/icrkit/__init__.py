"""icrkit: Independent Contact Regions on objects reconstructed from noisy range data.

NumPy in, NumPy out, over the C++ libraries (docs/python.md). Units are metres
and radians. Bad input raises ValueError with the same message as the
`icrkit` command; an internal error raises RuntimeError.
"""

import json as _json

from ._icrkit import _evaluate
from ._icrkit import (  # noqa: F401
    PointCloud,
    Reconstructor,
    TriangleMesh,
    ball_pivoting,
    independent_contact_regions,
    plan,
    read_mesh,
    read_point_cloud,
    read_tum_poses,
    reconstruct,
    sample_grasps,
    smooth,
    write_mesh,
    write_point_cloud,
)



def evaluate(cad, raw, filtered, name="dataset", grasps=200, fingers=(4, 5), seed=1, alpha=0.8, mu=0.8, edges=8,
             preselection=True, align=None, conservative=None, picks=20, patch_radius=None):
    """The paper's experiment (`icrkit evaluate`) on one object.

    `cad`, `raw`, `filtered`: TriangleMesh with unit vertex normals, in one
    frame (metres), or align="icp" to align raw and filtered to the CAD mesh
    first. `preselection`: honour the filtered mesh's `excluded` attribute.
    `conservative`: a list of K for uncertainty-aware growth beside the plain
    one. `patch_radius` (metres): also run every evaluated grasp with the
    reference library's patch contacts on all three meshes (records'
    `patch`, growth rows "patch"). Returns a dict: `records` (one dict per grasp, the fields of
    grasps.jsonl), `table1`, `eligibility` and `growth` (as table1.json,
    eligibility.json and conservative.json). docs/evaluation.md."""
    lines, table, eligibility, growth = _evaluate(
        cad, raw, filtered, name, grasps, list(fingers), seed, alpha, mu, edges, preselection, align or "none",
        list(conservative or []), picks, patch_radius)
    return {
        "records": [_json.loads(line) for line in lines],
        "table1": _json.loads(table),
        "eligibility": _json.loads(eligibility),
        "growth": _json.loads(growth),
    }


__all__ = [
    "evaluate",
    "PointCloud",
    "Reconstructor",
    "TriangleMesh",
    "ball_pivoting",
    "independent_contact_regions",
    "plan",
    "read_mesh",
    "read_point_cloud",
    "read_tum_poses",
    "reconstruct",
    "sample_grasps",
    "smooth",
    "write_mesh",
    "write_point_cloud",
]
