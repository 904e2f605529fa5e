# Type stubs of the icrkit package, so that editors complete the API.
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

Points = npt.NDArray[np.float64]  # (N, 3), C-contiguous, metres

class PointCloud:
    def __init__(self, points: Points, normals: Optional[Points] = ...) -> None: ...
    @property
    def points(self) -> Points: ...
    @property
    def normals(self) -> Optional[Points]: ...
    @property
    def attributes(self) -> Dict[str, npt.NDArray[np.float64]]: ...
    def set_attribute(self, name: str, values: npt.ArrayLike) -> None: ...
    def __len__(self) -> int: ...

class TriangleMesh:
    def __init__(self, vertices: Points, faces: npt.ArrayLike, normals: Optional[Points] = ...) -> None: ...
    @property
    def vertices(self) -> Points: ...
    @property
    def normals(self) -> Optional[Points]: ...
    @property
    def faces(self) -> npt.NDArray[np.int32]: ...
    @property
    def attributes(self) -> Dict[str, npt.NDArray[np.float64]]: ...
    def set_attribute(self, name: str, values: npt.ArrayLike) -> None: ...

def read_mesh(path: str) -> TriangleMesh: ...
def read_point_cloud(path: str) -> PointCloud: ...
def write_mesh(path: str, mesh: TriangleMesh) -> None: ...
def write_point_cloud(path: str, cloud: PointCloud) -> None: ...
def smooth(
    points: Union[Points, PointCloud],
    normals: Optional[Points] = ...,
    radius: Optional[float] = ...,
    radius_factor: float = ...,
    passes: int = ...,
    preselection: str = ...,
    viewpoint: Optional[Sequence[float]] = ...,
    window_normal_angle: float = ...,
) -> PointCloud: ...
def ball_pivoting(
    points: Union[Points, PointCloud], normals: Optional[Points] = ..., radii: Optional[Sequence[float]] = ...
) -> TriangleMesh: ...
def independent_contact_regions(
    mesh: TriangleMesh,
    contacts: Sequence[int],
    model: str = ...,
    mu: float = ...,
    edges: int = ...,
    mu_t: float = ...,
    alpha: float = ...,
    tws_radius: Optional[float] = ...,
    mode: str = ...,
    torque_reference: str = ...,
    excluded: Optional[npt.ArrayLike] = ...,
    conservative: Optional[float] = ...,
    normal_uncertainty: Optional[float] = ...,
    position_uncertainty: Optional[float] = ...,
    patch_radius: Optional[float] = ...,
) -> Dict[str, Any]: ...
def read_tum_poses(path: str) -> Tuple[np.ndarray, np.ndarray]: ...

class Reconstructor:
    def __init__(
        self,
        crop_box: Optional[Sequence[float]] = ...,
        auto_crop_half_size: float = ...,
        register: bool = ...,
        smoothing: str = ...,
        meshes: bool = ...,
        raw_mesh: bool = ...,
        register_as_scans_arrive: bool = ...,
    ) -> None: ...
    def add_depth(
        self,
        depth: np.ndarray,
        intrinsics: Sequence[float],
        pose: np.ndarray,
        timestamp: float = ...,
        depth_scale: float = ...,
        distortion: Optional[Sequence[float]] = ...,
        max_range: float = ...,
    ) -> None: ...
    def add_points(self, points: np.ndarray, pose: np.ndarray, timestamp: float = ..., max_range: float = ...) -> None: ...
    def __len__(self) -> int: ...
    @property
    def up_to_date(self) -> bool: ...
    @property
    def stored_bytes(self) -> int: ...
    def cloud(self, progress: Optional[Callable[[str, int, int], None]] = ...) -> PointCloud: ...
    def meshes(self, progress: Optional[Callable[[str, int, int], None]] = ...) -> Tuple[Optional[TriangleMesh], TriangleMesh]: ...
    def poses(self, reported: bool = ..., progress: Optional[Callable[[str, int, int], None]] = ...) -> np.ndarray: ...
    def report(self, progress: Optional[Callable[[str, int, int], None]] = ...) -> Dict[str, Any]: ...
    def write(self, directory: str, progress: Optional[Callable[[str, int, int], None]] = ...) -> None: ...

def reconstruct(
    input: str,
    poses: str = ...,
    intrinsics: Optional[Sequence[float]] = ...,
    depth_scale: Optional[float] = ...,
    progress: Optional[Callable[[str, int, int], None]] = ...,
) -> Dict[str, Any]: ...
def plan(
    mesh: TriangleMesh,
    fingers: Sequence[int] = ...,
    top: int = ...,
    candidates: int = ...,
    tws_radius: Optional[float] = ...,
    alpha: float = ...,
    model: str = ...,
    mu: float = ...,
    edges: int = ...,
    mu_t: float = ...,
    placement_error: float = ...,
    task_margin: float = ...,
    seed: int = ...,
    torque_reference: str = ...,
    excluded: Optional[npt.ArrayLike] = ...,
    mesh_path: str = ...,
    patch_radius: Optional[float] = ...,
) -> Dict[str, Any]: ...
def sample_grasps(
    mesh: TriangleMesh,
    fingers: int = ...,
    count: int = ...,
    seed: int = ...,
    min_epsilon: float = ...,
    model: str = ...,
    mu: float = ...,
    edges: int = ...,
    mu_t: float = ...,
    torque_reference: str = ...,
    excluded: Optional[npt.ArrayLike] = ...,
) -> List[Dict[str, Any]]: ...
def evaluate(
    cad: TriangleMesh,
    raw: TriangleMesh,
    filtered: TriangleMesh,
    name: str = ...,
    grasps: int = ...,
    fingers: Sequence[int] = ...,
    seed: int = ...,
    alpha: float = ...,
    mu: float = ...,
    edges: int = ...,
    preselection: bool = ...,
    align: Optional[str] = ...,
    conservative: Optional[Sequence[float]] = ...,
    picks: int = ...,
    patch_radius: Optional[float] = ...,
) -> Dict[str, Any]: ...
