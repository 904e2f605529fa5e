"""The icrkit Python package against known answers and against the icrkit
command (same numbers, bit for bit), and its input checks."""

import json
import os
import subprocess
import tempfile

import numpy as np
import pytest

import icrkit

DATA = os.environ.get("ICRKIT_SHARED_DATA_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data"))
ICRKIT = os.environ.get("ICRKIT")


def icosphere_like(n=40, radius=0.05):
    """A UV sphere: vertices, faces (outward, counter-clockwise) and exact normals."""
    verts = [(0.0, 0.0, radius)]
    for i in range(1, n):
        theta = np.pi * i / n
        for j in range(2 * n):
            phi = np.pi * j / n
            verts.append((radius * np.sin(theta) * np.cos(phi), radius * np.sin(theta) * np.sin(phi), radius * np.cos(theta)))
    verts.append((0.0, 0.0, -radius))
    verts = np.array(verts)
    faces = []
    ring = lambda i, j: 1 + (i - 1) * 2 * n + (j % (2 * n))
    for j in range(2 * n):
        faces.append((0, ring(1, j), ring(1, j + 1)))
    for i in range(1, n - 1):
        for j in range(2 * n):
            a, b, c, d = ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1)
            faces.append((a, b, c))
            faces.append((a, c, d))
    last = len(verts) - 1
    for j in range(2 * n):
        faces.append((ring(n - 1, j), last, ring(n - 1, j + 1)))
    normals = verts / np.linalg.norm(verts, axis=1, keepdims=True)
    return verts, np.array(faces, dtype=np.int32), normals


def test_arrays_are_views_and_round_trip_through_files():
    v, f, n = icosphere_like(12)
    mesh = icrkit.TriangleMesh(v, f, n)
    assert mesh.vertices.shape == v.shape and mesh.vertices.dtype == np.float64
    assert np.array_equal(mesh.vertices, v) and np.array_equal(mesh.faces, f)
    # A view, not a copy: writing through it changes the mesh.
    mesh.vertices[0, 0] = 1.0
    assert mesh.vertices[0, 0] == 1.0
    mesh.vertices[0, 0] = v[0, 0]
    mesh.set_attribute("region", np.arange(len(v)) % 3)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "sphere.ply")
        icrkit.write_mesh(path, mesh)
        back = icrkit.read_mesh(path)
    assert np.array_equal(back.vertices, mesh.vertices)
    assert np.array_equal(back.faces, mesh.faces)
    assert np.array_equal(back.attributes["region"], np.arange(len(v)) % 3)


def test_bad_arrays_and_files_give_clear_exceptions():
    with pytest.raises(ValueError, match=r"points: expected a float64 array of shape \(N, 3\), got a int64"):
        icrkit.PointCloud(np.zeros((4, 3), dtype=np.int64))
    with pytest.raises(ValueError, match=r"shape \(N, 3\), got a float64 array of shape \(4, 2\)"):
        icrkit.PointCloud(np.zeros((4, 2)))
    with pytest.raises(ValueError, match="not C-contiguous"):
        icrkit.PointCloud(np.zeros((3, 4))[:, :3])
    with pytest.raises(ValueError, match="no-such-file.ply"):
        icrkit.read_mesh("no-such-file.ply")
    v, f, n = icosphere_like(8)
    mesh = icrkit.TriangleMesh(v, f, n)
    with pytest.raises(ValueError, match="at least 2 contacts"):
        icrkit.independent_contact_regions(mesh, [0])
    contacts = icrkit.sample_grasps(mesh, count=1)[0]["contacts"]
    with pytest.raises(ValueError, match="normal_sigma and position_sigma"):
        icrkit.independent_contact_regions(mesh, contacts, conservative=1.0)
    with pytest.raises(ValueError, match="radius"):
        icrkit.independent_contact_regions(mesh, contacts, patch_radius=0.0)
    with pytest.raises(ValueError, match="radius"):
        icrkit.evaluate(mesh, mesh, mesh, grasps=1, fingers=(4,), patch_radius=-0.001)
    with pytest.raises(ValueError, match="expected frictional, frictionless or soft"):
        icrkit.independent_contact_regions(mesh, contacts, model="sticky")
    # Fixed bounds work on a mesh without sigmas, and shrink the regions.
    plain = icrkit.independent_contact_regions(mesh, contacts)
    cons = icrkit.independent_contact_regions(mesh, contacts, normal_uncertainty=0.005, position_uncertainty=1e-4)
    for p, c in zip(plain["regions"], cons["regions"]):
        assert set(c["vertices"].tolist()) <= set(p["vertices"].tolist())


def test_smoothing_a_noisy_plane_flattens_it_and_records_its_uncertainty():
    rng = np.random.default_rng(3)
    g = np.arange(60) * 0.001
    x, y = np.meshgrid(g, g)
    sigma = 0.0003
    points = np.column_stack([x.ravel(), y.ravel(), sigma * rng.standard_normal(x.size)])
    smoothed = icrkit.smooth(points, preselection="none")
    interior = (np.min(np.column_stack([x.ravel(), y.ravel(), 0.059 - x.ravel(), 0.059 - y.ravel()]), axis=1) > 0.006)
    assert np.sqrt(np.mean(smoothed.points[interior, 2] ** 2)) < 0.5 * sigma
    recorded = np.sqrt(np.mean(smoothed.attributes["position_sigma"][interior] ** 2))
    true = np.sqrt(np.mean(smoothed.points[interior, 2] ** 2))
    assert 0.8 * true < recorded < 1.25 * true


def test_ball_pivoting_meshes_a_sphere_sample_into_a_closed_surface():
    v, f, n = icosphere_like(30)
    mesh = icrkit.ball_pivoting(v, n)
    assert len(mesh.faces) > 0.9 * len(f)
    edges = np.sort(np.concatenate([mesh.faces[:, [0, 1]], mesh.faces[:, [1, 2]], mesh.faces[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert np.all(counts == 2), "every edge of a closed sphere has two faces"


@pytest.mark.skipif(not ICRKIT, reason="the icrkit command is needed for the comparison (ICRKIT unset)")
def test_regions_equal_the_commands_bit_for_bit():
    model = os.path.join(DATA, "icr-models", "Fish_5k.obj")
    if not os.path.exists(model):
        pytest.skip("shared data not found: " + model)
    mesh = icrkit.read_mesh(model)
    grasps = icrkit.sample_grasps(mesh, fingers=4, count=3, seed=5)
    assert len(grasps) == 3
    with tempfile.TemporaryDirectory() as tmp:
        out = subprocess.run([ICRKIT, "grasps", model, "--count", "3", "--seed", "5", "--json"],
                             check=True, capture_output=True, text=True)
        cli_grasps = json.loads(out.stdout)["grasps"]
        assert [g["contacts"] for g in grasps] == [g["contacts"] for g in cli_grasps]
        assert [g["epsilon"] for g in grasps] == [g["epsilon"] for g in cli_grasps]
        for g in grasps:
            contacts = ",".join(str(c) for c in g["contacts"])
            out = subprocess.run([ICRKIT, "icr", model, "--contacts", contacts, "-o", os.path.join(tmp, "r.ply"),
                                  "--json"], check=True, capture_output=True, text=True)
            cli = json.loads(out.stdout)
            py = icrkit.independent_contact_regions(mesh, g["contacts"])
            assert py["epsilon"] == cli["epsilon"] and py["gws_facets"] == cli["gws_facets"]
            for a, b in zip(py["regions"], cli["regions"]):
                assert a["vertices"].tolist() == b["vertices"] and a["area_m2"] == b["area_m2"]
                assert a["recommended"] == b["recommended"]


def test_plan_equals_the_commands_plan_json():
    model = os.path.join(DATA, "icr-models", "Fish_5k.obj")
    if not os.path.exists(model):
        pytest.skip("shared data not found: " + model)
    mesh = icrkit.read_mesh(model)
    plan = icrkit.plan(mesh, top=3, candidates=200, seed=2, mesh_path=model)
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "plan.json")
        subprocess.run([ICRKIT, "plan", model, "--top", "3", "--candidates", "200", "--seed", "2", "--renders", "0",
                        "-o", out, "--quiet"], check=True, capture_output=True, text=True)
        cli = json.load(open(out))
    for key in ("placement_error_m", "task_margin", "seed"):
        cli.pop(key)
    assert plan == cli
    assert [g["rank"] for g in plan["grasps"]] == [1, 2, 3]
    with pytest.raises(ValueError, match="top"):
        icrkit.plan(mesh, top=0)
    # Patch fingers, as --patch-radius.
    patched = icrkit.plan(mesh, top=2, candidates=200, seed=2, patch_radius=0.004)
    assert patched["patch"] == {"radius_m": 0.004, "filter_border": True} and len(patched["grasps"]) == 2
    assert plan["patch"] is None


def test_the_gil_is_released_during_long_calls():
    import threading
    import time
    v, f, n = icosphere_like(60)
    ticks = []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=ticker)
    t.start()
    start = time.perf_counter()
    icrkit.ball_pivoting(v, n)
    icrkit.smooth(v, n)
    elapsed = time.perf_counter() - start
    stop.set()
    t.join()
    during = [x for x in ticks if start <= x <= start + elapsed]
    if elapsed > 0.05:
        assert len(during) > 5, "another Python thread could not run while icrkit worked"


@pytest.mark.skipif(not ICRKIT, reason="the icrkit command is needed for the comparison (ICRKIT unset)")
def test_reconstruct_the_real_recording_as_the_command_does():
    rawlog = os.path.join(DATA, "primesense-bunny", "scans.rawlog")
    if not os.path.exists(rawlog):
        pytest.skip("shared data not found: " + rawlog)
    stages = set()
    result = icrkit.reconstruct(rawlog, progress=lambda stage, done, total: stages.add(stage))
    assert {"registration", "filtered mesh"} <= stages
    report = result["report"]
    assert report["scans"] == len(result["poses"]) and result["poses"].shape[1:] == (4, 4)
    assert report["filtered_mesh"]["non_manifold_edges"] == 0
    assert "normal_sigma" in result["filtered_mesh"].attributes
    with tempfile.TemporaryDirectory() as tmp:
        subprocess.run([ICRKIT, "reconstruct", rawlog, "-o", tmp, "--quiet"], check=True, capture_output=True)
        for name in ("raw", "filtered"):
            cli = icrkit.read_mesh(os.path.join(tmp, name + ".ply"))
            py = result[name + "_mesh"]
            assert np.array_equal(cli.vertices, py.vertices) and np.array_equal(cli.faces, py.faces), name


@pytest.mark.skipif(not ICRKIT, reason="the icrkit command is needed for the comparison (ICRKIT unset)")
def test_evaluate_gives_the_commands_records_and_table():
    model = os.path.join(DATA, "icr-models", "Fish_5k.obj")
    if not os.path.exists(model):
        pytest.skip("shared data not found: " + model)
    cad = icrkit.read_mesh(model)
    # A reconstruction stand-in: the same surface, vertices moved 0.3 mm along their normals.
    rng = np.random.default_rng(2)
    moved = cad.vertices + 0.0003 * rng.standard_normal((len(cad.vertices), 1)) * cad.normals
    noisy = icrkit.TriangleMesh(np.ascontiguousarray(moved), cad.faces, cad.normals)
    noisy.set_attribute("normal_sigma", np.full(len(moved), 0.01))
    noisy.set_attribute("position_sigma", np.full(len(moved), 0.0003))
    with tempfile.TemporaryDirectory() as tmp:
        noisy_path = os.path.join(tmp, "noisy.ply")
        icrkit.write_mesh(noisy_path, noisy)
        py = icrkit.evaluate(cad, icrkit.read_mesh(noisy_path), icrkit.read_mesh(noisy_path), name="Fish_5k",
                             grasps=4, fingers=(4,), conservative=[0.5], patch_radius=0.004)
        subprocess.run([ICRKIT, "evaluate", "--cad", model, "--raw", noisy_path, "--filtered", noisy_path,
                        "--grasps", "4", "--fingers", "4", "--conservative=0.5", "--patch-radius", "0.004",
                        "--renders", "0", "-o",
                        os.path.join(tmp, "run"), "--quiet"], check=True, capture_output=True)
        with open(os.path.join(tmp, "run", "grasps.jsonl")) as f:
            cli = [json.loads(line) for line in f if line.strip()]
        with open(os.path.join(tmp, "run", "table1.json")) as f:
            cli_table = json.load(f)
    assert py["records"] == cli
    assert py["table1"] == cli_table
    assert any(r["evaluated"] for r in py["records"])
    assert py["growth"]["sigmas"] == [0.5]
    assert any(r.get("patch", {}).get("evaluated") for r in py["records"])
    assert any(row["growth"] == "patch" for row in py["growth"]["rows"])
