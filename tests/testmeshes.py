"""Meshes the end-to-end CLI tests make for themselves: an icosphere with
exact normals, and the CAD / raw / filtered triple of an evaluation run."""
import math
import random
import struct

import plyfile


def icosphere(radius=0.05, subdivisions=3):
    """(positions, unit normals, faces) of a sphere: an icosahedron split
    `subdivisions` times, 10 * 4^s + 2 vertices, faces wound outwards."""
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
         (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
         (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        mid = {}

        def m(a, b):
            k = (min(a, b), max(a, b))
            if k not in mid:
                v.append(tuple((x + y) / 2 for x, y in zip(v[a], v[b])))
                mid[k] = len(v) - 1
            return mid[k]
        g = []
        for a, b, c in f:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            g += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = g
    n = [tuple(x / math.sqrt(sum(y * y for y in p)) for x in p) for p in v]
    p = [tuple(radius * x for x in q) for q in n]
    return p, n, f


def write_ascii_ply(path, positions, normals, faces, excluded=None):
    """ASCII PLY with x y z nx ny nz (and a uchar `excluded` when given)."""
    with open(path, 'w') as o:
        o.write('ply\nformat ascii 1.0\nelement vertex %d\n' % len(positions))
        o.write(''.join('property double %s\n' % s for s in ('x', 'y', 'z', 'nx', 'ny', 'nz')))
        if excluded is not None:
            o.write('property uchar excluded\n')
        o.write('element face %d\nproperty list uchar int vertex_indices\nend_header\n' % len(faces))
        for i, (q, r) in enumerate(zip(positions, normals)):
            extra = ' %d' % excluded[i] if excluded is not None else ''
            o.write('%.17g %.17g %.17g %.17g %.17g %.17g' % (q + r) + extra + '\n')
        o.writelines('3 %d %d %d\n' % t for t in faces)


def write_obj(path, positions, faces):
    """OBJ without normals."""
    with open(path, 'w') as o:
        o.writelines('v %.17g %.17g %.17g\n' % q for q in positions)
        o.writelines('f %d %d %d\n' % (a + 1, b + 1, c + 1) for a, b, c in faces)


def write_evaluation_meshes(cad_path, raw_path, filtered_path, seed=3):
    """From a CAD mesh with normals (binary PLY): a raw mesh = the CAD mesh
    pushed along its normals by 0.3 mm Gaussian noise, and a filtered mesh =
    an exact copy with every 97th vertex flagged `excluded`."""
    v, faces = plyfile.read(cad_path)
    n = len(v['x'][1])
    random.seed(seed)

    def write(path, noise, excluded_every):
        props = ['x', 'y', 'z', 'nx', 'ny', 'nz']
        head = ['ply', 'format binary_little_endian 1.0', 'element vertex %d' % n]
        head += ['property double %s' % p for p in props]
        if excluded_every:
            head.append('property uchar excluded')
        head += ['element face %d' % len(faces), 'property list uchar int vertex_indices', 'end_header']
        with open(path, 'wb') as out:
            out.write(('\n'.join(head) + '\n').encode())
            for i in range(n):
                s = random.gauss(0.0, noise) if noise else 0.0
                p = [v[k][1][i] for k in props]
                row = struct.pack('<6d', p[0] + s * p[3], p[1] + s * p[4], p[2] + s * p[5], p[3], p[4], p[5])
                if excluded_every:
                    row += struct.pack('<B', 1 if i % excluded_every == 0 else 0)
                out.write(row)
            for f in faces:
                out.write(struct.pack('<B3i', 3, *f))
    write(raw_path, 3e-4, 0)
    write(filtered_path, 0.0, 97)
