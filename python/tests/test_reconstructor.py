"""icrkit.Reconstructor: scans from NumPy arrays give what the folder path gives."""

import os
import tempfile

import numpy as np
import pytest

import icrkit

DATA = os.environ.get("ICRKIT_SHARED_DATA_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data"))
TUM = os.path.join(DATA, "primesense-bunny", "tum")
INTRINSICS = [542.0, 540.5, 320.0, 240.0]


def tum_frames():
    """The shared recording's depth images (uint16 mm) and reported camera poses (4x4, optical axes)."""
    image = pytest.importorskip("PIL.Image")
    if not os.path.exists(os.path.join(TUM, "depth.txt")):
        pytest.skip("shared data not found: " + TUM)
    rows = [l.split() for l in open(os.path.join(TUM, "depth.txt")) if l.strip() and not l.startswith("#")]
    _, poses = icrkit.read_tum_poses(os.path.join(TUM, "reported.txt"))
    for (stamp, name), pose in zip(rows, poses):
        yield float(stamp), np.asarray(image.open(os.path.join(TUM, name)), dtype=np.uint16), pose


def test_frames_from_memory_give_the_folders_meshes():
    frames = list(tum_frames())
    reconstructor = icrkit.Reconstructor()
    for stamp, depth, pose in frames:
        reconstructor.add_depth(depth, INTRINSICS, pose, timestamp=stamp)
    assert len(reconstructor) == 18 and not reconstructor.up_to_date
    raw, filtered = reconstructor.meshes()
    assert reconstructor.up_to_date
    folder = icrkit.reconstruct(TUM, poses=os.path.join(TUM, "reported.txt"), intrinsics=INTRINSICS, depth_scale=1000)
    for mine, theirs in ((raw, folder["raw_mesh"]), (filtered, folder["filtered_mesh"])):
        assert np.array_equal(mine.vertices, theirs.vertices) and np.array_equal(mine.faces, theirs.faces)
    assert np.array_equal(reconstructor.cloud().points, folder["cloud"].points)
    # Poses come back in the optical axes they went in with.
    assert np.allclose(reconstructor.poses(reported=True)[3], frames[3][2], atol=1e-9)
    report = reconstructor.report()
    assert report["scans"] == 18 and report["registration"]["pairs_accepted"] > 30
    assert report["input_format"] == "memory"
    # bun_zipper's frame, +y up, read from the poses (the table filter looks along it).
    assert report["up"] == [0.0, 1.0, 0.0] and report["up_automatic"]
    # The joint refinement, the registration's last step, is on and kept here.
    joint = report["registration"]["joint_refinement"]
    assert joint["enabled"] and joint["applied"] and joint["linked_view_pairs"] >= joint["graph_view_pairs"], joint
    with tempfile.TemporaryDirectory() as tmp:
        reconstructor.write(tmp)
        assert sorted(os.listdir(tmp)) == ["cloud.ply", "filtered.ply", "poses.txt", "raw.ply", "reconstruction.json"]
        assert np.array_equal(icrkit.read_mesh(os.path.join(tmp, "filtered.ply")).faces, filtered.faces)


def test_float_metres_and_strided_arrays_are_read_in_place():
    stamp, depth, pose = next(tum_frames())
    metres = depth.astype(np.float32) / 1000.0
    metres[depth == 0] = np.nan
    box = [-0.15, -0.1, -0.14, 0.14, 0.2, 0.16]  # one view: no axes to meet
    counts, floats, strided = (icrkit.Reconstructor(crop_box=box, register=False, meshes=False) for _ in range(3))
    wide = np.zeros((depth.shape[0], depth.shape[1] + 16), dtype=np.uint16)
    wide[:, :depth.shape[1]] = depth
    counts.add_depth(depth, INTRINSICS, pose, timestamp=stamp)
    floats.add_depth(metres, INTRINSICS, pose, timestamp=stamp)
    strided.add_depth(wide[:, :depth.shape[1]], INTRINSICS, pose, timestamp=stamp)
    a, b, c = counts.cloud().points, floats.cloud().points, strided.cloud().points
    assert np.array_equal(a, c)
    # The fused cloud is in Z-order of its points, which coordinates 1e-8 apart
    # may order differently near a cell's boundary: compared pixel by pixel.
    pa, pb = counts.cloud().attributes["pixel"], floats.cloud().attributes["pixel"]
    assert a.shape == b.shape and np.array_equal(np.sort(pa), np.sort(pb))
    assert np.abs(a[np.argsort(pa)] - b[np.argsort(pb)]).max() < 1e-5


def test_unorganised_points_and_errors():
    rng = np.random.default_rng(3)
    # A 10 cm sphere 0.6 m in front of four cameras around it.
    reconstructor = icrkit.Reconstructor(crop_box=[-0.15, -0.15, -0.15, 0.15, 0.15, 0.15], register=False)
    for k in range(4):
        angle = k * np.pi / 2
        pose = np.eye(4)
        forward = np.array([np.cos(angle), np.sin(angle), 0.0])
        down = np.array([0.0, 0.0, -1.0])
        right = np.cross(down, forward)
        pose[:3, :3] = np.column_stack([right, down, forward])
        pose[:3, 3] = -0.6 * forward
        d = rng.standard_normal((6000, 3))
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        world = 0.1 * d[(d @ -forward) > 0.2]
        local = (world - pose[:3, 3]) @ pose[:3, :3]
        local = np.vstack([local, [np.nan, np.nan, np.nan]])
        reconstructor.add_points(local, pose, timestamp=k)
    cloud = reconstructor.cloud()
    radius = np.linalg.norm(cloud.points, axis=1)
    assert len(radius) > 5000 and np.abs(radius - 0.1).max() < 0.004
    with pytest.raises(ValueError, match="uint16 counts or float32"):
        reconstructor.add_depth(np.zeros((4, 4), dtype=np.int32), INTRINSICS, np.eye(4))
    with pytest.raises(ValueError, match="4x4"):
        reconstructor.add_points(np.zeros((3, 3)), np.eye(3))
    with pytest.raises(ValueError, match="scan 4"):
        reconstructor.add_depth(np.zeros((4, 4), dtype=np.float32), [0.0, 1.0, 2.0, 2.0], np.eye(4))
    with pytest.raises(ValueError, match="no scans"):
        icrkit.Reconstructor().cloud()
    with pytest.raises(ValueError, match="up: expected a non-zero"):
        icrkit.Reconstructor(up=[0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="up: expected a non-zero"):
        icrkit.Reconstructor(up=[0.0, 1.0])
    given = icrkit.Reconstructor(crop_box=[-0.15, -0.15, -0.15, 0.15, 0.15, 0.15], register=False, meshes=False, up=[0, 0, 2])
    at = np.eye(4)
    at[2, 3] = -0.6
    given.add_points(0.1 * np.eye(3) + [0.0, 0.0, 0.6], at)
    assert given.report()["up"] == [0.0, 0.0, 1.0] and not given.report()["up_automatic"]


def test_a_thread_adds_while_another_asks_for_the_cloud():
    import threading

    frames = list(tum_frames())
    reference = icrkit.Reconstructor(meshes=False)
    for stamp, depth, pose in frames:
        reference.add_depth(depth, INTRINSICS, pose, timestamp=stamp)
    expected = reference.cloud().points

    shared = icrkit.Reconstructor(meshes=False)
    for stamp, depth, pose in frames[:6]:
        shared.add_depth(depth, INTRINSICS, pose, timestamp=stamp)

    def driver():
        for stamp, depth, pose in frames[6:]:
            shared.add_depth(depth, INTRINSICS, pose, timestamp=stamp)

    thread = threading.Thread(target=driver)
    thread.start()
    sizes = [len(shared.cloud().points)]  # whatever scans it holds at that moment
    thread.join()
    assert sizes[0] > 0 and len(shared) == 18
    assert np.array_equal(shared.cloud().points, expected)


def test_without_the_raw_baseline_only_the_filtered_mesh_is_made():
    frames = list(tum_frames())
    full, filtered_only = icrkit.Reconstructor(), icrkit.Reconstructor(raw_mesh=False)
    for stamp, depth, pose in frames:
        full.add_depth(depth, INTRINSICS, pose, timestamp=stamp)
        filtered_only.add_depth(depth, INTRINSICS, pose, timestamp=stamp)
    raw, filtered = filtered_only.meshes()
    assert raw is None
    assert np.array_equal(filtered.faces, full.meshes()[1].faces)
    with tempfile.TemporaryDirectory() as tmp:
        filtered_only.write(tmp)
        assert "raw.ply" not in os.listdir(tmp) and "filtered.ply" in os.listdir(tmp)


def test_without_the_joint_refinement_the_graphs_poses_stand():
    frames = list(tum_frames())
    default, graph_only = icrkit.Reconstructor(meshes=False), icrkit.Reconstructor(meshes=False, joint_refinement=False)
    for stamp, depth, pose in frames:
        default.add_depth(depth, INTRINSICS, pose, timestamp=stamp)
        graph_only.add_depth(depth, INTRINSICS, pose, timestamp=stamp)
    joint = graph_only.report()["registration"]["joint_refinement"]
    assert not joint["enabled"] and not joint["applied"] and joint["iterations"] == 0, joint
    # The step moves the views (tenths of a millimetre at the object).
    centre = np.mean(default.cloud().points, axis=0)
    moved = [np.linalg.norm((a @ np.linalg.inv(b) @ np.append(centre, 1.0))[:3] - centre)
             for a, b in zip(default.poses(), graph_only.poses())]
    assert 1e-5 < np.median(moved) < 5e-3, moved


def test_registered_as_the_scans_arrive():
    frames = list(tum_frames())
    together, arriving = icrkit.Reconstructor(meshes=False), icrkit.Reconstructor(meshes=False, register_as_scans_arrive=True)
    for i, (stamp, depth, pose) in enumerate(frames):
        together.add_depth(depth, INTRINSICS, pose, timestamp=stamp)
        arriving.add_depth(depth, INTRINSICS, pose, timestamp=stamp)
        if i == 8:
            assert len(arriving.poses()) == 9  # solved on demand; more scans may follow
    report = arriving.report()
    assert report["registration"]["pairs_accepted"] > 30
    kept = report["registration"]["model_alignment"]["views_kept"]  # per level, of the 17 after the first
    assert len(kept) == 4 and min(kept) >= 14  # 6, 4, 2 and 1 cm cells
    # Each view registered with the earlier ones, not all together: close to,
    # not equal to, the folder's poses (measured 0.1-1.2 mm at the object).
    centre = np.mean(arriving.cloud().points, axis=0)
    for mine, theirs in zip(arriving.poses(), together.poses()):
        moved = mine @ np.linalg.inv(theirs) @ np.append(centre, 1.0)
        assert np.linalg.norm(moved[:3] - centre) < 3e-3
    # Registering as the scans arrive needs the registration.
    try:
        icrkit.Reconstructor(register=False, register_as_scans_arrive=True)
        assert False, "expected a ValueError"
    except ValueError as e:
        assert "incremental" in str(e), e
