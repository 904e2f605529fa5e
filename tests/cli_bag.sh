#!/usr/bin/env bash
# `icrkit reconstruct BAG.mcap`: ROS 2 bags written by an independent writer
# (tests/bags/write_bag.mjs: @mcap/core, @foxglove/rosmsg2-serialization,
# zstd and lz4 chunks). The shared bunny recording written as a bag must
# reconstruct byte for byte as its TUM folder, with poses from the
# PoseStamped topic (zstd chunks) and from tf (lz4 chunks); small bags in
# all three chunk forms read alike; bad bags exit 2 with one line naming the
# topic or the chunk, and write nothing. Skipped (77) without node/npm, the
# npm packages (`npm ci --prefix tests/bags`) or the shared data. Needs $ICRKIT.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/cli_common.sh"

skip() { echo "SKIP: $*" >&2; exit 77; }

bags="$root/tests/bags"
command -v node >/dev/null && command -v npm >/dev/null || skip "node and npm are needed to write the test bags"
if [ ! -d "$bags/node_modules/@mcap/core" ] || [ ! -d "$bags/node_modules/@foxglove/rosmsg2-serialization" ]; then
  npm ci --prefix "$bags" --no-audit --no-fund >"$work/npm.log" 2>&1 ||
    skip "the npm packages of tests/bags could not be installed (npm ci --prefix tests/bags): $(tail -1 "$work/npm.log")"
fi
write_bag() { node "$bags/write_bag.mjs" "$@" 2>"$work/node_err" || { echo "FAIL: write_bag.mjs $*: $(cat "$work/node_err")" >&2; exit 1; }; }

expect_exit 0 "$ICRKIT" reconstruct --help
for option in --depth-topic --camera-info-topic --pose-topic --frames; do
  grep -q -- "$option" "$work/out" || fail "reconstruct --help lacks $option"
done

# --- Small bags: the same images in plain, zstd and lz4 chunks.
write_bag errors "$work/small"
small_flags=(--no-meshes --no-plane-removal --crop -1,-1,0,1,1,2 -q)
for kind in good good_zstd good_lz4; do
  "$ICRKIT" reconstruct "$work/small/$kind.mcap" -o "$work/small_$kind" "${small_flags[@]}" --json \
    >"$work/small_$kind.json" 2>"$work/err" || fail "reconstruct $kind.mcap failed: $(cat "$work/err")"
done
for kind in good_zstd good_lz4; do
  cmp -s "$work/small_good/cloud.ply" "$work/small_$kind/cloud.ply" || fail "$kind.mcap: cloud.ply differs from good.mcap's"
done
py "
import json
d = json.load(open('$work/small_good_lz4.json'))
assert d == json.load(open('$work/small_good_lz4/reconstruction.json')), 'stdout and reconstruction.json differ'
b = d['bag']
assert b['depth_topic'] == '/camera/depth/image_raw' and b['camera_info_topic'] == '/camera/depth/camera_info', b
assert b['pose_source'] == 'topic' and b['pose_topic'] == '/camera/pose' and b['images'] == 4, b
assert d['pose_matching'] == 'topic', d['pose_matching']
assert d['input_format'] == 'ros2_bag', d['input_format']
assert d['depth_camera']['intrinsics_source'] == '/camera/depth/camera_info', d['depth_camera']
assert d['depth_camera']['depth_scale'] == 1000 and d['scans'] == 4, d['depth_camera']
" || fail "the small bag's summary is wrong"

# --- Bad bags: exit 2, one line naming the topic or the chunk, nothing written.
expect_input_error "missing_camera_info.mcap:topic /camera/depth/camera_info: no sensor_msgs/msg/CameraInfo" \
  "$ICRKIT" reconstruct "$work/small/missing_camera_info.mcap" -o "$work/bad1" "${small_flags[@]}"
expect_input_error "rgb8.mcap:topic /camera/depth/image_raw: unknown depth image encoding 'rgb8'" \
  "$ICRKIT" reconstruct "$work/small/rgb8.mcap" -o "$work/bad2" "${small_flags[@]}"
expect_input_error "bad_crc.mcap:chunk at byte [0-9]*: CRC-32" \
  "$ICRKIT" reconstruct "$work/small/bad_crc.mcap" -o "$work/bad3" "${small_flags[@]}"
expect_input_error "bad_zstd.mcap:chunk at byte [0-9]*: zstd: " \
  "$ICRKIT" reconstruct "$work/small/bad_zstd.mcap" -o "$work/bad4" "${small_flags[@]}"
expect_input_error "pose_gap.mcap:topic /camera/pose: no pose within 0.020000000 s of image 1 of /camera/depth/image_raw (stamp 101.000000000)" \
  "$ICRKIT" reconstruct "$work/small/pose_gap.mcap" -o "$work/bad5" "${small_flags[@]}"
expect_input_error "topic /no/such: no such topic" \
  "$ICRKIT" reconstruct "$work/small/good.mcap" -o "$work/bad6" "${small_flags[@]}" --pose-topic /no/such
expect_input_error "good.mcap:topic /tf: holds no transform" \
  "$ICRKIT" reconstruct "$work/small/good.mcap" -o "$work/bad7" "${small_flags[@]}" --frames world,camera_depth_optical_frame
expect_input_error "^icrkit: --pose-topic" \
  "$ICRKIT" reconstruct "$work/small/good.mcap" -o "$work/bad8" "${small_flags[@]}" --pose-topic /camera/pose --frames world
expect_input_error "^icrkit: --poses" \
  "$ICRKIT" reconstruct "$work/small/good.mcap" -o "$work/bad9" "${small_flags[@]}" --poses "$work/small/good.mcap"
expect_input_error "^icrkit: --depth-topic: applies to a ROS 2 bag" \
  "$ICRKIT" reconstruct "$work/small" -o "$work/bad10" --depth-topic /x
for n in 1 2 3 4 5 6 7 8 9 10; do
  [ ! -e "$work/bad$n" ] || fail "a refused bag left output behind (bad$n)"
done

# --- The shared bunny recording: bag == TUM folder, byte for byte.
data="${ICRKIT_SHARED_DATA_DIR:-}"
tum="$data/primesense-bunny/tum"
if [ -z "$data" ] || [ ! -f "$tum/depth.txt" ] || [ ! -f "$tum/reported.txt" ]; then
  echo "note: shared primesense-bunny data not found under '${data}'; the byte comparison is skipped" >&2
  [ "$failures" -eq 0 ] || exit 1
  exit 77
fi
intrinsics=542,540.5,320,240
write_bag tum "$tum" "$work/bunny_zstd.mcap" --intrinsics "$intrinsics" --compression zstd
write_bag tum "$tum" "$work/bunny_lz4.mcap" --intrinsics "$intrinsics" --compression lz4
"$ICRKIT" reconstruct "$tum" --intrinsics "$intrinsics" --depth-scale 1000 --poses "$tum/reported.txt" \
  -o "$work/bunny_tum" -q >/dev/null 2>"$work/err" || fail "reconstruct of the TUM folder failed: $(cat "$work/err")"
"$ICRKIT" reconstruct "$work/bunny_zstd.mcap" --pose-topic /camera/pose -o "$work/bunny_topic" -q --json \
  >"$work/bunny_topic.json" 2>"$work/err" || fail "reconstruct of the bag (--pose-topic) failed: $(cat "$work/err")"
"$ICRKIT" reconstruct "$work/bunny_lz4.mcap" --frames world,camera_depth_optical_frame -o "$work/bunny_tf" -q --json \
  >"$work/bunny_tf.json" 2>"$work/err" || fail "reconstruct of the bag (--frames) failed: $(cat "$work/err")"
for run in bunny_topic bunny_tf; do
  for f in cloud.ply raw.ply filtered.ply poses.txt; do
    cmp -s "$work/bunny_tum/$f" "$work/$run/$f" || fail "$run: $f differs from the TUM folder's"
  done
done
py "
import json
t = json.load(open('$work/bunny_topic.json')); f = json.load(open('$work/bunny_tf.json'))
assert t['pose_matching'] == 'topic' and t['bag']['pose_topic'] == '/camera/pose', (t['pose_matching'], t['bag'])
assert f['pose_matching'] == 'tf', f['pose_matching']
assert f['bag']['frames'] == ['world', 'camera_depth_optical_frame'], f['bag']
assert t['scans'] == f['scans'] == 18, (t['scans'], f['scans'])
" || fail "the bunny bag summaries are wrong"

[ "$failures" -eq 0 ] || exit 1
echo "cli_bag: all checks passed"
