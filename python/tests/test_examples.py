"""The Python examples run as a user would run them."""

import os
import subprocess
import sys
import tempfile

import pytest

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "python")


def run(script, output, *args):
    with tempfile.TemporaryDirectory() as tmp:
        out = subprocess.run([sys.executable, os.path.join(EXAMPLES, script), *args, "-o", os.path.join(tmp, output)],
                             capture_output=True, text=True, env=dict(os.environ), timeout=300)
        assert out.returncode == 0, out.stderr
        produced = os.listdir(tmp)
    return out.stdout, produced


def test_icr_on_a_mesh_plots_the_regions():
    pytest.importorskip("matplotlib")
    stdout, produced = run("icr_on_a_mesh.py", "regions.png")
    assert "finger 3:" in stdout and "aim at vertex" in stdout
    assert produced


def test_open3d_interop_goes_both_ways():
    pytest.importorskip("open3d")
    stdout, produced = run("open3d_interop.py", "mesh.ply")
    assert "Open3D: area" in stdout and produced
    area = float(stdout.split("Open3D: area ")[1].split()[0])
    assert abs(area - 314.2) < 0.05 * 314.2, stdout


def test_streaming_the_shared_folder_plans_grasps():
    pytest.importorskip("PIL")
    folder = os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data", "primesense-bunny", "tum")
    if not os.path.exists(os.path.join(folder, "depth.txt")):
        pytest.skip("shared data not found: " + folder)
    stdout, produced = run("stream_tum_folder.py", "out", folder, "--top", "3")
    assert "18 scans fed" in stdout and "grasp 1:" in stdout, stdout


def test_streaming_with_registration_as_the_frames_arrive():
    pytest.importorskip("PIL")
    folder = os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data", "primesense-bunny", "tum")
    if not os.path.exists(os.path.join(folder, "depth.txt")):
        pytest.skip("shared data not found: " + folder)
    stdout, produced = run("stream_tum_folder.py", "out", folder, "--top", "1", "--as-they-arrive")
    assert "18 scans fed" in stdout and "grasp 1:" in stdout, stdout
