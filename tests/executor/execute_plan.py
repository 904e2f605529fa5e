#!/usr/bin/python3
"""An independent executor of icrkit's plan.json on the true object (a CAD mesh).

It shares no code with icrkit: its own mesh readers, wrench code, ray casting
and scipy's ConvexHull (qhull through scipy) for the grasp wrench space. A
finger is executed *by touch*: aimed at a point q of the reconstruction with
the reconstruction's normal n there, it starts at q + s n and moves along -n;
it touches the first CAD triangle it crosses whose normal faces it (back faces
are passed through: a finger never touches the inside of a wall). The contact
is that point with that triangle's normal.

Per planned grasp: the aimed grasp (every finger at its region's recommended
contact), random picks (one vertex of every region, with the reconstruction's
vertex normal) and placement-error trials (every finger aimed at its
recommended contact plus a 2-D Gaussian offset in its tangent plane). A grasp
holds when its wrenches' convex hull holds the TWS ball of the plan's radius.

Usage: execute_plan.py PLAN --cad CAD [--mesh M] [--compute-normals] [--transform F] [--top K]
       [--picks N] [--placement-samples N] [--placement-error S] [--standoff S]
       [--seed N] [--json OUT]
Exit 0 after an execution, 2 on bad input (one line naming the file).
"""
import argparse
import json
import math
import struct
import sys

import numpy as np
from scipy.spatial import ConvexHull, cKDTree
from scipy.spatial import QhullError


class InputError(Exception):
    pass


# --- meshes ----------------------------------------------------------------

_PLY_TYPES = {'char': 'i1', 'uchar': 'u1', 'short': '<i2', 'ushort': '<u2', 'int': '<i4', 'uint': '<u4',
              'float': '<f4', 'double': '<f8', 'int8': 'i1', 'uint8': 'u1', 'int16': '<i2', 'uint16': '<u2',
              'int32': '<i4', 'uint32': '<u4', 'float32': '<f4', 'float64': '<f8'}


def _read_ply(path):
    data = open(path, 'rb').read()
    end = data.find(b'end_header')
    if not data.startswith(b'ply') or end < 0:
        raise InputError(f'{path}: not a PLY file (no "ply" magic or no end_header)')
    header_end = data.index(b'\n', end) + 1
    lines = data[:header_end].decode('ascii', 'replace').splitlines()
    fmt = None
    elements = []
    for line in lines:
        w = line.split()
        if not w:
            continue
        if w[0] == 'format':
            fmt = w[1]
        elif w[0] == 'element':
            elements.append((w[1], int(w[2]), []))
        elif w[0] == 'property':
            if not elements:
                raise InputError(f'{path}: property before any element')
            if w[1] == 'list':
                elements[-1][2].append((w[4], 'list', w[2], w[3]))
            else:
                if w[1] not in _PLY_TYPES:
                    raise InputError(f'{path}: unknown PLY type {w[1]!r}')
                elements[-1][2].append((w[2], w[1]))
    if fmt not in ('binary_little_endian', 'ascii'):
        raise InputError(f'{path}: PLY format {fmt!r} is not supported (binary_little_endian or ascii)')
    out = {}
    if fmt == 'ascii':
        tokens = data[header_end:].split()
        pos = 0
        for name, count, props in elements:
            rows = []
            for _ in range(count):
                row = {}
                for p in props:
                    if p[1] == 'list':
                        n = int(tokens[pos]); pos += 1
                        row[p[0]] = [float(t) for t in tokens[pos:pos + n]]; pos += n
                    else:
                        row[p[0]] = float(tokens[pos]); pos += 1
                rows.append(row)
            out[name] = rows
        vertices = out.get('vertex', [])
        verts = {k: np.array([r[k] for r in vertices]) for k in (vertices[0].keys() if vertices else [])}
        faces = [r.get('vertex_indices', r.get('vertex_index')) for r in out.get('face', [])]
        return verts, faces
    pos = header_end
    verts, faces = {}, []
    for name, count, props in elements:
        if all(p[1] != 'list' for p in props):
            dtype = np.dtype([(p[0], _PLY_TYPES[p[1]]) for p in props])
            size = dtype.itemsize * count
            if pos + size > len(data):
                raise InputError(f'{path}: element {name} truncated (expected {count} rows)')
            arr = np.frombuffer(data, dtype=dtype, count=count, offset=pos)
            pos += size
            if name == 'vertex':
                verts = {p[0]: arr[p[0]].astype(float) for p in props}
            continue
        # A list element (faces): parse row by row, fast path for one uchar+int list.
        rows = []
        for i in range(count):
            row = {}
            for p in props:
                if p[1] == 'list':
                    ct, it = np.dtype(_PLY_TYPES[p[2]]), np.dtype(_PLY_TYPES[p[3]])
                    n = int(np.frombuffer(data, ct, 1, pos)[0]); pos += ct.itemsize
                    row[p[0]] = np.frombuffer(data, it, n, pos).astype(np.int64); pos += it.itemsize * n
                else:
                    t = np.dtype(_PLY_TYPES[p[1]])
                    row[p[0]] = np.frombuffer(data, t, 1, pos)[0]; pos += t.itemsize
            rows.append(row)
        if name == 'face':
            faces = [r.get('vertex_indices', r.get('vertex_index')) for r in rows]
    return verts, faces


def _triangulate(faces, path, vertex_count):
    tris = []
    for k, f in enumerate(faces):
        if f is None or len(f) < 3:
            raise InputError(f'{path}: face {k}: expected at least 3 vertex indices')
        f = [int(i) for i in f]
        if min(f) < 0 or max(f) >= vertex_count:
            raise InputError(f'{path}: face {k}: vertex index out of range for {vertex_count} vertices')
        for j in range(1, len(f) - 1):
            tris.append((f[0], f[j], f[j + 1]))
    return np.array(tris, dtype=np.int64).reshape(-1, 3)


def _read_obj(path):
    v, vn, faces, face_normals = [], [], [], []
    for number, line in enumerate(open(path, encoding='ascii', errors='replace'), 1):
        w = line.split()
        if not w:
            continue
        try:
            if w[0] == 'v':
                v.append([float(x) for x in w[1:4]])
            elif w[0] == 'vn':
                vn.append([float(x) for x in w[1:4]])
            elif w[0] == 'f':
                idx, nidx = [], []
                for t in w[1:]:
                    parts = t.split('/')
                    i = int(parts[0])
                    idx.append(i - 1 if i > 0 else len(v) + i)
                    if len(parts) >= 3 and parts[2]:
                        j = int(parts[2])
                        nidx.append(j - 1 if j > 0 else len(vn) + j)
                faces.append(idx)
                face_normals.append(nidx if len(nidx) == len(idx) else None)
        except ValueError:
            raise InputError(f'{path}: line {number}: expected numbers in {w[0]!r} record')
    verts = {'x': np.array([p[0] for p in v]), 'y': np.array([p[1] for p in v]), 'z': np.array([p[2] for p in v])}
    if vn and all(fn is not None for fn in face_normals):
        normals = np.zeros((len(v), 3))
        for f, fn in zip(faces, face_normals):
            for i, j in zip(f, fn):
                normals[i] = vn[j]
        verts['nx'], verts['ny'], verts['nz'] = normals[:, 0], normals[:, 1], normals[:, 2]
    return verts, faces


class Mesh:
    def __init__(self, path):
        try:
            if path.lower().endswith('.obj'):
                verts, faces = _read_obj(path)
            else:
                verts, faces = _read_ply(path)
        except OSError as e:
            raise InputError(f'{path}: cannot be read ({e.strerror})')
        except (struct.error, ValueError, IndexError) as e:
            raise InputError(f'{path}: malformed ({e})')
        if not all(k in verts for k in ('x', 'y', 'z')):
            raise InputError(f'{path}: expected vertex properties x, y, z')
        self.path = path
        self.positions = np.stack([verts['x'], verts['y'], verts['z']], axis=1)
        self.normals = None
        if all(k in verts for k in ('nx', 'ny', 'nz')):
            n = np.stack([verts['nx'], verts['ny'], verts['nz']], axis=1)
            self.normals = n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
        self.triangles = _triangulate(faces, path, len(self.positions))

    def compute_normals(self):
        """Vertex normals from the faces (area-weighted, the winding's side), as icrkit's --compute-normals."""
        t = self.triangles
        a, b, c = (self.positions[t[:, k]] for k in range(3))
        face = np.cross(b - a, c - a)
        n = np.zeros_like(self.positions)
        for k in range(3):
            np.add.at(n, t[:, k], face)
        length = np.linalg.norm(n, axis=1, keepdims=True)
        self.normals = np.where(length > 0, n / np.maximum(length, 1e-300), 0.0)
        return self


class ToucherOnCad:
    """Ray casting onto the CAD mesh: the first front-facing triangle along a finger's approach."""

    def __init__(self, cad):
        self.cad = cad
        t = cad.triangles
        if len(t) == 0:
            raise InputError(f'{cad.path}: has no faces; the executor needs the true surface')
        a, b, c = (cad.positions[t[:, k]] for k in range(3))
        n = np.cross(b - a, c - a)
        length = np.linalg.norm(n, axis=1)
        keep = length > 0
        self.a, self.e1, self.e2 = a[keep], (b - a)[keep], (c - a)[keep]
        self.face_normals = n[keep] / length[keep, None]
        # Winding outward: the signed volume of a closed (or nearly closed) surface is positive.
        volume = np.sum(np.einsum('ij,ij->i', a[keep], np.cross(b[keep], c[keep]))) / 6.0
        self.flipped = volume < 0
        if self.flipped:
            self.face_normals = -self.face_normals
            print(f'execute_plan: {cad.path}: faces wound inwards (negative volume); normals flipped', file=sys.stderr)
        centroids = (self.a + (self.a + self.e1) + (self.a + self.e2)) / 3.0
        self.radius = float(np.max(np.linalg.norm(np.stack([self.a, self.a + self.e1, self.a + self.e2], 1)
                                                  - centroids[:, None, :], axis=2)))
        self.tree = cKDTree(centroids)

    def touch(self, q, n, standoff):
        """(point, unit normal) where a finger aimed at q along -n touches, or None."""
        n = n / np.linalg.norm(n)
        origin = q + standoff * n
        direction = -n
        length = 2.0 * standoff
        # Candidate triangles: centroids within reach of samples along the segment.
        step = max(self.radius, 1e-4)
        samples = origin[None, :] + np.outer(np.arange(0.0, length + step, step), direction)
        cand = set()
        for lst in self.tree.query_ball_point(samples, step + self.radius):
            cand.update(lst)
        if not cand:
            return None
        idx = np.fromiter(cand, dtype=np.int64)
        # Moller-Trumbore, vectorised over the candidates.
        e1, e2 = self.e1[idx], self.e2[idx]
        p = np.cross(direction[None, :], e2)
        det = np.einsum('ij,ij->i', e1, p)
        ok = np.abs(det) > 1e-18
        inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
        s = origin[None, :] - self.a[idx]
        u = np.einsum('ij,ij->i', s, p) * inv
        qv = np.cross(s, e1)
        v = (qv @ direction) * inv
        t = np.einsum('ij,ij->i', e2, qv) * inv
        facing = self.face_normals[idx] @ n > 0.0
        # A ray through a vertex or an edge (a finger aimed at a mesh vertex of
        # the CAD itself) must not slip through the crack between triangles.
        tol = 1e-9
        hit = ok & (u >= -tol) & (v >= -tol) & (u + v <= 1 + tol) & (t >= 0) & (t <= length) & facing
        if not np.any(hit):
            return None
        k = np.argmin(np.where(hit, t, np.inf))
        return origin + t[k] * direction, self.face_normals[idx[k]]


# --- wrenches --------------------------------------------------------------

def local_primitives(model):
    kind = model.get('type', 'frictional')
    f = float(model.get('force_n', 1.0))
    prims = []  # (force xyz in the contact frame, torsion)
    if kind == 'frictionless' or model.get('include_normal', True):
        prims.append((np.array([0.0, 0.0, f]), 0.0))
    if kind == 'frictionless':
        return prims
    if kind not in ('frictional', 'soft'):
        raise InputError(f'plan model type {kind!r}: expected frictional, frictionless or soft')
    half = math.atan(float(model['mu']))
    edges = int(model['edges'])
    for k in range(edges):
        t = -math.pi + 2.0 * math.pi * k / edges
        prims.append((np.array([f * math.sin(half) * math.cos(t), f * math.sin(half) * math.sin(t),
                                f * math.cos(half)]), 0.0))
    if kind == 'soft':
        mu_t = float(model['mu_t'])
        prims.append((np.array([0.0, 0.0, f]), mu_t * f))
        prims.append((np.array([0.0, 0.0, f]), -mu_t * f))
    return prims


def rotation_from_z(n):
    z = np.array([0.0, 0.0, 1.0])
    axis = np.cross(z, n)
    s = np.linalg.norm(axis)
    c = n[2]
    if s < 1e-12:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + k + k @ k * ((1.0 - c) / (s * s))


def contact_wrenches(points, normals, model, reference, lam):
    prims = local_primitives(model)
    columns = []
    for p, n in zip(points, normals):
        n = n / np.linalg.norm(n)
        r = rotation_from_z(n)
        arm = p - reference
        for force_local, torsion in prims:
            force = r @ force_local
            torque = np.cross(arm, force) + torsion * n
            columns.append(np.concatenate([force, torque / lam]))
    return np.array(columns)


def grasp_epsilon(wrenches):
    """Distance from the origin to the hull's nearest facet; <= 0 when the origin is not inside."""
    try:
        hull = ConvexHull(wrenches)
    except (QhullError, ValueError):
        return 0.0
    # Interior: normal . x + offset <= 0, so the origin's distance to facet i is -offset_i.
    return float(np.min(-hull.equations[:, -1]))


def holds(wrenches, radius):
    e = grasp_epsilon(wrenches)
    return e > 0.0 and e >= radius * (1.0 - 1e-9)


# --- execution -------------------------------------------------------------

def tangent_basis(n):
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t1 = np.cross(n, helper)
    t1 /= np.linalg.norm(t1)
    return t1, np.cross(n, t1)


def _execute(aims, toucher, plan, radius, standoff, transform):
    """Touches every finger's aim (q, n); (held, epsilon, missed)."""
    rot, shift = transform
    points, normals = [], []
    for q, n in aims:
        q = rot @ q + shift
        n = rot @ n
        contact = toucher.touch(q, n, standoff)
        if contact is None:
            return False, 0.0, True
        points.append(contact[0])
        normals.append(contact[1])
    reference = rot @ np.asarray(plan['torque_reference_m'], float) + shift
    w = contact_wrenches(points, normals, plan['model'], reference, float(plan['lambda_m']))
    e = grasp_epsilon(w)
    return e > 0.0 and e >= radius * (1.0 - 1e-9), e, False


def read_transform(path):
    try:
        data = json.load(open(path))
    except (OSError, ValueError) as e:
        raise InputError(f'{path}: expected a JSON 4x4 matrix ({e})')
    m = data.get('matrix') if isinstance(data, dict) else data
    m = np.asarray(m, float)
    if m.shape != (4, 4):
        raise InputError(f'{path}: expected a 4x4 matrix (a list of 4 rows, or {{"matrix": ...}})')
    return m[:3, :3], m[:3, 3]


def execute_plan(plan, recon, cad, top=None, picks=100, placement_samples=100, placement_error=0.003,
                 standoff=0.02, seed=1, transform=None):
    if recon.normals is None:
        raise InputError(f'{recon.path}: the reconstructed mesh needs vertex normals (nx, ny, nz)')
    toucher = ToucherOnCad(cad)
    transform = transform or (np.eye(3), np.zeros(3))
    rng = np.random.default_rng(seed)
    results = []
    grasps = plan['grasps'][:top] if top else plan['grasps']
    for gi, g in enumerate(grasps):
        regions = g['regions']
        radius = float(g['tws_radius'])
        for r in regions:
            if not r['vertices']:
                raise InputError(f'plan grasps[{gi}]: a region is empty')
            if max(r['vertices']) >= len(recon.positions):
                raise InputError(f'plan grasps[{gi}]: vertex id beyond the {len(recon.positions)} vertices of '
                                 f'{recon.path}')
        aimed = [(np.asarray(r['recommended']['position'], float), np.asarray(r['recommended']['normal'], float))
                 for r in regions]
        held, eps, missed = _execute(aimed, toucher, plan, radius, standoff, transform)
        out = {'rank': g['rank'], 'aimed_held': held, 'aimed_epsilon': eps, 'missed_contacts': int(missed),
               'picks': picks, 'picks_held': 0, 'placement': placement_samples, 'placement_held': 0,
               'region_areas_m2': [r['area_m2'] for r in regions], 'tws_radius': radius}
        for _ in range(picks):
            aims = []
            for r in regions:
                v = r['vertices'][rng.integers(len(r['vertices']))]
                aims.append((recon.positions[v], recon.normals[v]))
            h, _, m = _execute(aims, toucher, plan, radius, standoff, transform)
            out['picks_held'] += int(h)
            out['missed_contacts'] += int(m)
        for _ in range(placement_samples):
            aims = []
            for q, n in aimed:
                n = n / np.linalg.norm(n)
                t1, t2 = tangent_basis(n)
                a, b = rng.normal(0.0, placement_error, 2)
                aims.append((q + a * t1 + b * t2, n))
            h, _, m = _execute(aims, toucher, plan, radius, standoff, transform)
            out['placement_held'] += int(h)
            out['missed_contacts'] += int(m)
        results.append(out)
    areas = [a for r in results for a in r['region_areas_m2']]
    summary = {
        'grasps': len(results),
        'aimed_held_fraction': sum(r['aimed_held'] for r in results) / max(len(results), 1),
        'picks_held_fraction': sum(r['picks_held'] for r in results) / max(sum(r['picks'] for r in results), 1),
        'placement_held_fraction': (sum(r['placement_held'] for r in results)
                                    / max(sum(r['placement'] for r in results), 1)),
        'median_region_area_m2': float(np.median(areas)) if areas else 0.0,
    }
    return {'grasps': results, 'summary': summary}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('plan')
    ap.add_argument('--cad', required=True, help='the true object (PLY or OBJ)')
    ap.add_argument('--mesh', help="the plan's mesh (default: the plan's \"mesh\")")
    ap.add_argument('--compute-normals', action='store_true',
                    help="derive the plan mesh's vertex normals from its faces (a mesh without normals)")
    ap.add_argument('--transform', help='JSON 4x4 matrix taking the plan mesh to the CAD frame')
    ap.add_argument('--top', type=int)
    ap.add_argument('--picks', type=int, default=100)
    ap.add_argument('--placement-samples', type=int, default=100)
    ap.add_argument('--placement-error', type=float, default=0.003)
    ap.add_argument('--standoff', type=float, default=0.02)
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--json')
    a = ap.parse_args(argv)
    try:
        try:
            plan = json.load(open(a.plan))
        except (OSError, ValueError) as e:
            raise InputError(f'{a.plan}: expected plan.json ({e})')
        for key in ('mesh', 'model', 'torque_reference_m', 'lambda_m', 'grasps'):
            if key not in plan:
                raise InputError(f'{a.plan}: expected the key {key!r}')
        recon = Mesh(a.mesh or plan['mesh'])
        if a.compute_normals:
            recon.compute_normals()
        cad = Mesh(a.cad)
        transform = read_transform(a.transform) if a.transform else None
        result = execute_plan(plan, recon, cad, a.top, a.picks, a.placement_samples, a.placement_error,
                              a.standoff, a.seed, transform)
    except InputError as e:
        print(f'execute_plan: {e}', file=sys.stderr)
        return 2
    for g in result['grasps']:
        print(f"rank {g['rank']:2d}: aimed {'held' if g['aimed_held'] else 'FAILED'} (epsilon {g['aimed_epsilon']:.4f}"
              f" / task {g['tws_radius']:.4f}), picks {100.0 * g['picks_held'] / max(g['picks'], 1):5.1f} %, "
              f"placement {100.0 * g['placement_held'] / max(g['placement'], 1):5.1f} %, "
              f"median area {np.median(g['region_areas_m2']) * 1e6:.0f} mm2")
    s = result['summary']
    print(f"summary: {s['grasps']} grasps, aimed {100 * s['aimed_held_fraction']:.1f} %, picks "
          f"{100 * s['picks_held_fraction']:.1f} %, placement {100 * s['placement_held_fraction']:.1f} %, median "
          f"region area {s['median_region_area_m2'] * 1e6:.0f} mm2")
    if a.json:
        with open(a.json + '.tmp', 'w') as f:
            json.dump(result, f)
        import os
        os.replace(a.json + '.tmp', a.json)
    return 0


if __name__ == '__main__':
    sys.exit(main())
