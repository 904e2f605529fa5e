#!/usr/bin/python3
"""Seed corpora of icrkit's fuzz targets (./run fuzz): small hand-made
inputs of every form each reader accepts (ASCII and binary, both byte
orders, gzip and plain), the files of ../shared/data when present (skipped
otherwise) and the kept regression inputs.

  tests/fuzz/make_seeds.py OUT_DIR [SHARED_DATA_DIR]

Writes OUT_DIR/<target>/<name> for every target of fuzz_targets.cpp.
"""
import gzip
import json
import os
import shutil
import struct
import sys

out = sys.argv[1]
shared = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data")
root = os.path.dirname(os.path.abspath(__file__))


def put(target, name, data):
    d = os.path.join(out, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def copy(target, path, limit=2 << 20):
    if os.path.isfile(path) and os.path.getsize(path) <= limit:
        put(target, os.path.basename(path), open(path, "rb").read())


# A tetrahedron, the smallest closed mesh.
V = [(0, 0, 0), (0.01, 0, 0), (0, 0.01, 0), (0, 0, 0.01)]
F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def ply(fmt):
    header = (f"ply\nformat {fmt} 1.0\ncomment fuzz seed\nelement vertex {len(V)}\n"
              "property float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
              "property float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
              "property float confidence\n"
              f"element face {len(F)}\nproperty list uchar int vertex_indices\nend_header\n")
    if fmt == "ascii":
        body = "".join(f"{x} {y} {z} 0 0 1 255 0 0 0.5\n" for x, y, z in V)
        body += "".join(f"3 {a} {b} {c}\n" for a, b, c in F)
        return (header + body).encode()
    e = "<" if fmt == "binary_little_endian" else ">"
    body = b"".join(struct.pack(e + "6f3Bf", x, y, z, 0, 0, 1, 255, 0, 0, 0.5) for x, y, z in V)
    body += b"".join(struct.pack(e + "B3i", 3, a, b, c) for a, b, c in F)
    return header.encode() + body


for fmt in ("ascii", "binary_little_endian", "binary_big_endian"):
    put("ply", f"tetra_{fmt}.ply", ply(fmt))
put("ply", "points_double.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\n"
    "property double z\nelement range_grid 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 1 1\n1 0\n")

obj = "# fuzz seed\no tetra\n" + "".join(f"v {x} {y} {z}\n" for x, y, z in V)
obj += "vn 0 0 1\nvt 0 0\n" + "".join(f"f {a + 1}/1/1 {b + 1}//1 {c + 1}\n" for a, b, c in F)
put("obj", "tetra.obj", obj)
put("obj", "quad_negative.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4 -3 -2 -1\n")
copy("obj", os.path.join(root, "..", "..", "datasets", "tetrahedron.obj"))

pcd_head = ("# .PCD v0.7\nVERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\n"
            f"WIDTH {len(V)}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {len(V)}\n")
put("pcd", "tetra_ascii.pcd", pcd_head + "DATA ascii\n" + "".join(f"{x} {y} {z} 4278190335\n" for x, y, z in V))
put("pcd", "tetra_binary.pcd", (pcd_head + "DATA binary\n").encode() +
    b"".join(struct.pack("<3fI", x, y, z, 0xFF0000FF) for x, y, z in V))

put("xyz", "tetra.xyz", "".join(f"{x} {y} {z}\n" for x, y, z in V))
put("xyz", "normals.xyz", "# x y z nx ny nz\n0 0 0 0 0 1\n0.01 0 0 0 0 1\n")

put("tum_depth_list", "depth.txt", "# timestamp filename\n1000.0 depth/1000.png\n1001.5 depth/1001.png\n")
put("tum_poses", "poses.txt", "# timestamp tx ty tz qx qy qz qw\n1000.0 0.1 0 0.7 0 0 0 1\n1001.5 0 0.1 0.7 0 0.7071068 0 0.7071068\n")
put("camera_json", "camera.json", json.dumps({"fx": 542, "fy": 540.5, "cx": 320, "cy": 240, "width": 640, "height": 480,
                                              "depth_scale": 1000, "max_range_m": 4.0,
                                              "distortion_k1_k2_p1_p2_k3": [0.01, -0.02, 0, 0, 0]}))
put("camera_json", "calibrated.json", json.dumps({"camera": {"fx": 580, "fy": 580, "cx": 319.5, "cy": 239.5}, "depth_scale": 5000}))
put("range_model_json", "model.json", json.dumps({
    "format": "icrkit range error model 1", "model": "e(r) = offset + slope r + sine sin(2 pi r / wavelength) + ...",
    "wavelength_m": 5.0, "offset_m": 0.004, "slope": -0.001, "sine_m": 0.002, "cosine_m": -0.001,
    "calibration": {"scans": 12, "samples": 4000, "rejected": 3, "min_range_m": 0.5, "max_range_m": 2.0,
                    "rms_before_m": 0.006, "rms_after_m": 0.002}}))



# A small ROS 2 bag (MCAP, CDR): two 4x3 16UC1 depth images, a CameraInfo,
# a PoseStamped topic and tf (dynamic world -> base, static base -> cam),
# in an uncompressed chunk (and an lz4 one when python3-lz4 is there).
def mcap_bag(compress=None):
    def record(op, body):
        return bytes([op]) + struct.pack("<Q", len(body)) + body

    def text(value):
        return struct.pack("<I", len(value)) + value.encode()

    class Cdr:
        def __init__(self):
            self.b = bytearray(b"\x00\x01\x00\x00")

        def put(self, fmt, value):
            size = struct.calcsize(fmt)
            while (len(self.b) - 4) % size:
                self.b.append(0)
            self.b += struct.pack("<" + fmt, value)
            return self

        def string(self, value):
            self.put("I", len(value) + 1)
            self.b += value.encode() + b"\x00"
            return self

        def header(self, stamp, frame):
            return self.put("i", stamp).put("I", 0).string(frame)

    def image(stamp):
        c = Cdr().header(stamp, "cam").put("I", 3).put("I", 4).string("16UC1").put("B", 0).put("I", 8).put("I", 24)
        c.b += struct.pack("<12H", *([1000] * 12))
        return bytes(c.b)

    info = Cdr().header(1, "cam").put("I", 3).put("I", 4).string("plumb_bob").put("I", 5)
    for v in [0.0] * 5 + [2.0, 0.0, 1.5, 0.0, 2.0, 1.0, 0.0, 0.0, 1.0] + [0.0] * 21:
        info.put("d", v)

    def pose(stamp, x):
        c = Cdr().header(stamp, "world")
        for v in (x, 0.0, 0.5, 0.0, 0.0, 0.0, 1.0):
            c.put("d", v)
        return bytes(c.b)

    def tf(stamp, parent, child, x):
        c = Cdr().put("I", 1).header(stamp, parent).string(child)
        for v in (x, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0):
            c.put("d", v)
        return bytes(c.b)

    topics = [("/camera/depth/image_raw", "sensor_msgs/msg/Image"), ("/camera/depth/camera_info", "sensor_msgs/msg/CameraInfo"),
              ("/camera/pose", "geometry_msgs/msg/PoseStamped"), ("/tf", "tf2_msgs/msg/TFMessage"),
              ("/tf_static", "tf2_msgs/msg/TFMessage")]
    out = b"\x89MCAP0\r\n" + record(1, text("ros2") + text("icrkit seeds"))
    for i, (topic, schema) in enumerate(topics, 1):
        out += record(3, struct.pack("<H", i) + text(schema) + text("ros2msg") + struct.pack("<I", 0))
        out += record(4, struct.pack("<HH", i, i) + text(topic) + text("cdr") + struct.pack("<I", 0))

    def message(channel, data):
        return record(5, struct.pack("<HIQQ", channel, 0, 0, 0) + data)

    records = message(2, bytes(info.b)) + message(5, tf(0, "base", "cam", 0.1))
    for stamp in (1, 2):
        records += message(3, pose(stamp, 0.01 * stamp)) + message(4, tf(stamp, "world", "base", 0.01 * stamp))
        records += message(1, image(stamp))
    import zlib
    stored, name = (records, "") if compress is None else compress(records)
    out += record(6, struct.pack("<QQQI", 0, 0, len(records), zlib.crc32(records)) + text(name) +
                  struct.pack("<Q", len(stored)) + stored)
    return out + record(0x0F, struct.pack("<I", 0)) + record(2, bytes(20)) + b"\x89MCAP0\r\n"


put("mcap", "depth_pose_tf.mcap", mcap_bag())
try:
    import lz4.frame
    put("mcap", "depth_pose_tf_lz4.mcap", mcap_bag(lambda data: (lz4.frame.compress(data), "lz4")))
except ImportError:
    pass

# Regions against the targets' 8-vertex strip (record_targets.cpp).
put("regions_json", "regions.json", json.dumps({"regions": [
    {"finger": 0, "contact": 1, "vertices": [0, 1, 2], "area_m2": 1e-4, "recommended": {"vertex": 1, "depth_m": 0.001}},
    {"finger": 1, "contact": 4, "vertices": [3, 4, 5]}]}))

# Files the commands wrote (tests/fuzz/seeds/): plans, grasp lines.
seeds = os.path.join(root, "seeds")
for target in os.listdir(seeds):
    for name in os.listdir(os.path.join(seeds, target)):
        copy(target, os.path.join(seeds, target, name))

# The shared recordings and models, when present.
if os.path.isdir(shared):
    rawlog = os.path.join(shared, "primesense-bunny", "scans.rawlog")
    copy("rawlog", rawlog)
    if os.path.isfile(rawlog):
        data = open(rawlog, "rb").read()
        if data[:2] == b"\x1f\x8b":
            put("rawlog", "scans_plain.rawlog", gzip.decompress(data)[: 2 << 20])
    copy("tum_depth_list", os.path.join(shared, "primesense-bunny", "tum", "depth.txt"))
    for name in ("reported.txt", "groundtruth.txt"):
        copy("tum_poses", os.path.join(shared, "primesense-bunny", "tum", name))
    copy("pcd", os.path.join(shared, "pcl-views", "milk.pcd"))  # binary_compressed
    copy("obj", os.path.join(shared, "icr-models", "sphere.obj"), 256 << 10)
    copy("ply", os.path.join(shared, "stanford-bunny", "bun000.ply"), 1 << 20)
mrpt = "/usr/share/mrpt/datasets/tests_rgbd.rawlog"
copy("rawlog", mrpt)

# Every input a fuzzer ever crashed on seeds its target again.
kept = os.path.join(root, "..", "fuzz-regressions")
if os.path.isdir(kept):
    for target in os.listdir(kept):
        for name in os.listdir(os.path.join(kept, target)):
            copy(target, os.path.join(kept, target, name))
