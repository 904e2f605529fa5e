"""Known answers for the independent executor (execute_plan.py): its wrenches,
its hull test and its by-touch contacts, without icrkit's code."""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
import pytest

pytest.importorskip('scipy')  # scripts/install-deps.sh installs python3-scipy
sys.path.insert(0, os.path.dirname(__file__))
import execute_plan as ex  # noqa: E402

FRICTIONAL = {'type': 'frictional', 'mu': 0.8, 'mu_t': 0.5, 'edges': 8}


def write_ascii_ply(path, positions, triangles, normals=None):
    with open(path, 'w') as f:
        f.write('ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n'
                % len(positions))
        if normals is not None:
            f.write('property float nx\nproperty float ny\nproperty float nz\n')
        f.write('property uchar excluded\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n'
                % len(triangles))
        for k, p in enumerate(positions):
            row = list(p) + (list(normals[k]) if normals is not None else []) + [0]
            f.write(' '.join(str(x) for x in row) + '\n')
        for t in triangles:
            f.write('3 %d %d %d\n' % tuple(t))


def cube(size=0.04):
    """A closed cube, faces wound outwards, two triangles per side."""
    h = size / 2
    corners = np.array([[x, y, z] for x in (-h, h) for y in (-h, h) for z in (-h, h)])
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = []
    for a, b, c, d in quads:
        tris += [(a, b, c), (a, c, d)]
    return corners, np.array(tris)


def test_wrench_convention_matches_the_documented_primitives():
    w = ex.contact_wrenches([np.zeros(3)], [np.array([0.0, 0.0, 1.0])], FRICTIONAL, np.zeros(3), 1.0)
    assert w.shape == (9, 6)  # the normal force and 8 cone edges
    np.testing.assert_allclose(w[0], [0, 0, 1, 0, 0, 0])
    half = np.arctan(0.8)
    np.testing.assert_allclose(np.linalg.norm(w[1:, :3], axis=1), 1.0)
    np.testing.assert_allclose(w[1:, 2], np.cos(half))
    # Torques about the reference, divided by lambda: a contact 1 m along x
    # pushing along z makes a torque -1 about y; lambda 2 halves it.
    w = ex.contact_wrenches([np.array([1.0, 0, 0])], [np.array([0.0, 0, 1])], {'type': 'frictionless'},
                            np.zeros(3), 2.0)
    np.testing.assert_allclose(w[0], [0, 0, 1, 0, -0.5, 0])
    soft = dict(FRICTIONAL, type='soft')
    w = ex.contact_wrenches([np.zeros(3)], [np.array([0.0, 0, 1])], soft, np.zeros(3), 1.0)
    assert w.shape == (11, 6)
    np.testing.assert_allclose(w[-1], [0, 0, 1, 0, 0, -0.5])


def test_two_frictionless_fingers_never_hold_and_four_frictional_ones_do():
    h = 0.02
    points = [np.array([h, 0, 0]), np.array([-h, 0, 0])]
    normals = [np.array([1.0, 0, 0]), np.array([-1.0, 0, 0])]
    w = ex.contact_wrenches(points, normals, {'type': 'frictionless'}, np.zeros(3), h)
    assert ex.grasp_epsilon(w) <= 0.0
    assert not ex.holds(w, 1e-6)
    points = [np.array([h, 0.005, 0]), np.array([-h, -0.005, 0]), np.array([0, h, 0.005]), np.array([0, -h, -0.005])]
    normals = [np.array([1.0, 0, 0]), np.array([-1.0, 0, 0]), np.array([0, 1.0, 0]), np.array([0, -1.0, 0])]
    w = ex.contact_wrenches(points, normals, FRICTIONAL, np.zeros(3), h)
    e = ex.grasp_epsilon(w)
    assert e > 0.0
    # The grasp turned by 90 deg about z is the same grasp: the same epsilon.
    turn = np.array([[0, -1.0, 0], [1.0, 0, 0], [0, 0, 1.0]])
    w2 = ex.contact_wrenches([turn @ p for p in points], [turn @ n for n in normals], FRICTIONAL, np.zeros(3), h)
    assert abs(ex.grasp_epsilon(w2) - e) < 1e-9
    assert ex.holds(w, 0.999 * e) and not ex.holds(w, 1.001 * e)


def test_a_finger_touches_the_side_of_a_thin_wall_that_faces_it(tmp_path):
    # Two sheets 2 mm apart, the top one facing +z, the bottom one -z (a cup wall).
    n = 4
    grid = np.array([[x, y] for y in np.linspace(-0.02, 0.02, n + 1) for x in np.linspace(-0.02, 0.02, n + 1)])
    top = np.column_stack([grid, np.full(len(grid), 0.001)])
    bottom = np.column_stack([grid, np.full(len(grid), -0.001)])
    tris = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            b, c, d = a + 1, a + n + 2, a + n + 1
            tris += [(a, b, c), (a, c, d)]  # +z
    base = len(top)
    tris += [(base + a, base + c, base + b) for a, b, c in tris[:]]  # the bottom sheet, -z
    path = tmp_path / 'wall.ply'
    write_ascii_ply(path, np.vstack([top, bottom]), tris)
    toucher = ex.ToucherOnCad(ex.Mesh(str(path)))
    # Aimed 1.7 mm below the top sheet (nearer the bottom one), approaching from above.
    point, normal = toucher.touch(np.array([0.003, 0.004, -0.0007]), np.array([0.0, 0, 1.0]), 0.02)
    np.testing.assert_allclose(point, [0.003, 0.004, 0.001], atol=1e-12)
    np.testing.assert_allclose(normal, [0, 0, 1.0])
    # From below it touches the bottom sheet.
    point, normal = toucher.touch(np.array([0.003, 0.004, 0.0007]), np.array([0.0, 0, -1.0]), 0.02)
    np.testing.assert_allclose(point[2], -0.001, atol=1e-12)
    # Beyond the wall there is nothing to touch.
    assert toucher.touch(np.array([0.05, 0.0, 0.0]), np.array([0.0, 0, 1.0]), 0.02) is None


def test_a_plan_on_the_cad_mesh_itself_holds_everywhere(tmp_path):
    icrkit = os.environ.get('ICRKIT')
    if not icrkit or not os.path.exists(icrkit):
        pytest.skip('ICRKIT (the icrkit binary) is not set')
    # An ellipsoid, meshed finely: planned on itself, every aimed grasp and pick holds.
    import math
    rings, segments = 40, 80
    pos, nrm, tris = [], [], []
    axes = np.array([0.05, 0.04, 0.03])
    for i in range(rings + 1):
        th = math.pi * i / rings
        for j in range(segments):
            ph = 2 * math.pi * j / segments
            u = np.array([math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph), math.cos(th)])
            pos.append(axes * u)
            g = u / axes
            nrm.append(g / np.linalg.norm(g))
    for i in range(rings):
        for j in range(segments):
            a, b = i * segments + j, i * segments + (j + 1) % segments
            c, d = a + segments, b + segments
            if i > 0:
                tris.append((a, b, d))
            if i < rings - 1:
                tris.append((a, d, c))
    mesh = tmp_path / 'ellipsoid.ply'
    write_ascii_ply(mesh, pos, tris, nrm)
    plan = tmp_path / 'plan.json'
    subprocess.run([icrkit, 'plan', str(mesh), '--top', '3', '--candidates', '300', '--tws-radius', '0.05',
                    '--renders', '0', '-o', str(plan), '-q'], check=True, stdout=subprocess.DEVNULL)
    result = ex.execute_plan(json.load(open(plan)), ex.Mesh(str(mesh)), ex.Mesh(str(mesh)), picks=40,
                             placement_samples=10)
    s = result['summary']
    assert s['grasps'] == 3
    assert s['aimed_held_fraction'] == 1.0
    assert s['picks_held_fraction'] == 1.0
    # Bad input: exit 2, one line naming the file.
    bad = subprocess.run([sys.executable, ex.__file__, str(plan), '--cad', str(tmp_path / 'missing.ply')],
                         capture_output=True, text=True)
    assert bad.returncode == 2
    assert 'missing.ply' in bad.stderr and bad.stderr.count('\n') == 1


def test_a_plan_on_a_scanned_object_holds_on_itself():
    """Real data: Stanford's bunny, meshed from real range scans (shared data)."""
    icrkit = os.environ.get('ICRKIT')
    data = os.environ.get('ICRKIT_SHARED_DATA_DIR') or os.path.join(os.path.dirname(__file__), '..', '..', '..',
                                                                     'shared', 'data')
    model = os.path.join(data, 'stanford-bunny', 'bun_zipper.ply')
    if not icrkit or not os.path.exists(icrkit):
        pytest.skip('ICRKIT (the icrkit binary) is not set')
    if not os.path.exists(model):
        pytest.skip('SKIPPED: shared data not found: ' + model)
    with tempfile.TemporaryDirectory() as tmp:
        plan = os.path.join(tmp, 'plan.json')
        subprocess.run([icrkit, 'plan', model, '--compute-normals', '--top', '3', '--candidates', '300', '--alpha',
                        '0.5', '--renders', '0', '-o', plan, '-q'], check=True, stdout=subprocess.DEVNULL)
        mesh = ex.Mesh(model).compute_normals()
        result = ex.execute_plan(json.load(open(plan)), mesh, mesh, picks=30, placement_samples=5)
    s = result['summary']
    assert s['grasps'] == 3
    assert s['aimed_held_fraction'] == 1.0
    # By touch on the mesh itself the contact normal is the face's, not the
    # vertex's; the regions, grown with a 25 % task margin, absorb that.
    assert s['picks_held_fraction'] >= 0.99, s
