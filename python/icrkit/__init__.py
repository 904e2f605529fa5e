"""icrkit: Independent Contact Regions on objects reconstructed from noisy range data.

NumPy in, NumPy out, over the C++ libraries (docs/python.md). Units are metres
and radians. Bad input raises ValueError with the same message as the
`icrkit` command; an internal error raises RuntimeError.
"""

from ._icrkit import (  # noqa: F401
    PointCloud,
    TriangleMesh,
    ball_pivoting,
    independent_contact_regions,
    read_mesh,
    read_point_cloud,
    reconstruct,
    sample_grasps,
    smooth,
    write_mesh,
    write_point_cloud,
)

__all__ = [
    "PointCloud",
    "TriangleMesh",
    "ball_pivoting",
    "independent_contact_regions",
    "read_mesh",
    "read_point_cloud",
    "reconstruct",
    "sample_grasps",
    "smooth",
    "write_mesh",
    "write_point_cloud",
]
