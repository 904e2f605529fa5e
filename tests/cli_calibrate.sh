#!/usr/bin/env bash
# End-to-end checks of `icrkit calibrate`: checkerboard images rendered here
# (numpy) through a known camera give back its intrinsics; a rawlog without
# a board and bad arguments give exit code 2 and one line; --write-rawlog
# copies a recording with the new camera. Needs $ICRKIT.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/cli_common.sh"

expect_exit 0 "$ICRKIT" calibrate --help
grep -q -- "--board" "$work/out" && grep -q -- "--write-rawlog" "$work/out" || fail "calibrate --help lacks its options"

# Eight views of a 9x6 (inner corners) board with 25 mm squares through a
# 640x480 camera, fx 580, fy 578, cx 322.5, cy 236, k1 -0.12, k2 0.05,
# rendered with 3x3 supersampling, written as binary PGM.
mkdir -p "$work/boards"
py "
import numpy as np
fx, fy, cx, cy, k1, k2 = 580.0, 578.0, 322.5, 236.0, -0.12, 0.05
sq, cols, rows = 0.025, 10, 7
def rot(a, b, c):
    ca, sa, cb, sb, cc, sc = np.cos(a), np.sin(a), np.cos(b), np.sin(b), np.cos(c), np.sin(c)
    rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    rz = np.array([[cc, -sc, 0], [sc, cc, 0], [0, 0, 1]])
    return rz @ ry @ rx
poses = [((0, 0, 0), (-0.10, -0.07, 0.5)), ((0.35, 0, 0.1), (-0.02, -0.05, 0.55)), ((-0.35, 0.05, -0.1), (-0.16, -0.02, 0.52)),
         ((0, 0.4, 0.05), (-0.12, -0.10, 0.48)), ((0.05, -0.4, 0), (-0.05, -0.02, 0.6)), ((0.3, 0.3, 0.2), (-0.14, -0.08, 0.58)),
         ((-0.3, -0.3, -0.2), (-0.06, -0.03, 0.5)), ((0.25, -0.25, 0.4), (-0.11, -0.09, 0.62))]
s = (np.arange(3) + 0.5) / 3 - 0.5
u, v = np.meshgrid(np.arange(640), np.arange(480))
for n, (angles, t) in enumerate(poses):
    R, t = rot(*angles), np.array(t)
    acc = np.zeros((480, 640))
    for du in s:
        for dv in s:
            xd, yd = (u + du - cx) / fx, (v + dv - cy) / fy
            x, y = xd.copy(), yd.copy()
            for _ in range(30):  # invert the radial model by fixed-point steps
                r2 = x * x + y * y
                f = 1 + k1 * r2 + k2 * r2 * r2
                x, y = xd / f, yd / f
            d = np.stack([x, y, np.ones_like(x)], -1)
            nrm = R[:, 2]
            p = d * ((nrm @ t) / (d @ nrm))[..., None]
            b = (p - t) @ R  # board coordinates
            i, j = np.floor(b[..., 0] / sq) + 1, np.floor(b[..., 1] / sq) + 1
            inside = (i >= 0) & (i < cols) & (j >= 0) & (j < rows)
            margin = (b[..., 0] > -2 * sq) & (b[..., 0] < (cols) * sq) & (b[..., 1] > -2 * sq) & (b[..., 1] < rows * sq)
            val = np.where(inside & ((i + j) % 2 == 0), 20.0, np.where(margin, 235.0, 120.0))
            acc += val
    img = np.clip(np.round(acc / 9), 0, 255).astype(np.uint8)
    with open('$work/boards/board_%02d.pgm' % n, 'wb') as f:
        f.write(b'P5\n640 480\n255\n' + img.tobytes())
" || { echo "could not render the boards" >&2; exit 1; }

"$ICRKIT" calibrate --images "$work/boards" --board 9x6 --square 0.025 -o "$work/camera.json" --json \
  >"$work/cal.json" 2>"$work/err" || fail "calibrate failed: $(cat "$work/err")"
py "
import json
d = json.load(open('$work/cal.json'))
c = d['camera']
assert d['images'] == 8 and d['boards_found'] >= 6, d
assert d['rms_reprojection_px'] < 0.5, d['rms_reprojection_px']
for key, want in (('fx', 580.0), ('fy', 578.0), ('cx', 322.5), ('cy', 236.0)):
    assert abs(c[key] - want) < 0.01 * want, (key, c[key], want)
assert c['width'] == 640 and c['height'] == 480
f = json.load(open('$work/camera.json'))
assert f['camera'] == c, 'the -o file differs from the summary'
" || fail "calibration from rendered boards is off: $(cat "$work/cal.json")"

# A simulated recording: its scans show no full board; --write-rawlog copies it.
"$ICRKIT" simulate --object cup --views 2 -o "$work/rec" -q >/dev/null || fail "simulate failed"
expect_input_error "found in 0 of 2 images" "$ICRKIT" calibrate --rawlog "$work/rec/scans.rawlog"
expect_input_error "--images/--rawlog" "$ICRKIT" calibrate
expect_input_error "--images/--rawlog" "$ICRKIT" calibrate --images "$work/boards" --rawlog "$work/rec/scans.rawlog"
expect_input_error "--write-rawlog.*needs --rawlog" "$ICRKIT" calibrate --images "$work/boards" --write-rawlog "$work/x.rawlog"
expect_input_error "--board" "$ICRKIT" calibrate --images "$work/boards" --board 1x6
expect_input_error "--board" "$ICRKIT" calibrate --images "$work/boards" --board nine
expect_input_error "missing" "$ICRKIT" calibrate --images "$work/missing"

if [ "$failures" -gt 0 ]; then
  echo "$failures check(s) failed" >&2
  exit 1
fi
echo "all calibrate CLI checks passed"
