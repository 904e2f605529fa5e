// Writes ROS 2 bags (MCAP, CDR) for icrkit's tests with writers that share
// no code with icrkit: @mcap/core for the records and chunks,
// @foxglove/rosmsg2-serialization for the messages, @foxglove/wasm-zstd and
// lz4js for the chunk compression, pngjs for the TUM depth PNGs.
//
//   node write_bag.mjs tum FOLDER OUT.mcap --intrinsics fx,fy,cx,cy [--compression zstd|lz4|none]
//       depth.txt's images (16UC1) on /camera/depth/image_raw, CameraInfo on
//       /camera/depth/camera_info, reported.txt's poses (TUM optical frame,
//       matched by order as the folder reader matches an equal count) on
//       /camera/pose and as /tf world -> base, with /tf_static base ->
//       camera_depth_optical_frame, all stamped with the image's stamp.
//   node write_bag.mjs errors DIR
//       small bags that icrkit must refuse (see writeErrorBags).
import { McapWriter } from "@mcap/core";
import { parse } from "@foxglove/rosmsg";
import { MessageWriter } from "@foxglove/rosmsg2-serialization";
import zstd from "@foxglove/wasm-zstd";
import lz4 from "lz4js";
import pngjs from "pngjs";
import fs from "node:fs";
import path from "node:path";

const SEPARATOR = "\n================================================================================\n";
const TIME = "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec";
const HEADER = "MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id";
const DEFINITIONS = {
  "sensor_msgs/msg/Image": [
    "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\nuint32 step\nuint8[] data",
    HEADER, TIME],
  "sensor_msgs/msg/CameraInfo": [
    "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\nfloat64[] d\nfloat64[9] k\n" +
      "float64[9] r\nfloat64[12] p\nuint32 binning_x\nuint32 binning_y\nsensor_msgs/RegionOfInterest roi",
    HEADER, TIME,
    "MSG: sensor_msgs/RegionOfInterest\nuint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify"],
  "geometry_msgs/msg/PoseStamped": [
    "std_msgs/Header header\ngeometry_msgs/Pose pose", HEADER, TIME,
    "MSG: geometry_msgs/Pose\ngeometry_msgs/Point position\ngeometry_msgs/Quaternion orientation",
    "MSG: geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z",
    "MSG: geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w"],
  "tf2_msgs/msg/TFMessage": [
    "geometry_msgs/TransformStamped[] transforms",
    "MSG: geometry_msgs/TransformStamped\nstd_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform",
    HEADER, TIME,
    "MSG: geometry_msgs/Transform\ngeometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation",
    "MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z",
    "MSG: geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w"],
};

function compressor(method) {
  if (method === "zstd") return (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 3) });
  if (method === "lz4") return (data) => ({ compression: "lz4", compressedData: Uint8Array.from(lz4.compress(data)) });
  if (method === "none") return undefined;
  if (typeof method === "function") return method;
  throw new Error(`unknown compression ${method}`);
}

// A bag written in memory, then to `file` at close().
class Bag {
  constructor(file, compression, chunkSize = 4 << 20) {
    this.file = file;
    this.parts = [];
    let position = 0n;
    const parts = this.parts;
    this.writer = new McapWriter({
      writable: {
        position: () => position,
        write: async (buffer) => { parts.push(Buffer.from(buffer)); position += BigInt(buffer.byteLength); },
      },
      chunkSize,
      compressChunk: compressor(compression),
    });
    this.channels = new Map();
    this.writers = new Map();
  }
  async start() { await this.writer.start({ profile: "ros2", library: "icrkit tests/bags/write_bag.mjs" }); }
  async topic(topic, type) {
    if (!this.writers.has(type)) {
      const text = DEFINITIONS[type].join(SEPARATOR);
      const schemaId = await this.writer.registerSchema({ name: type, encoding: "ros2msg", data: new TextEncoder().encode(text) });
      this.writers.set(type, { schemaId, writer: new MessageWriter(parse(text, { ros2: true })) });
    }
    const { schemaId } = this.writers.get(type);
    const id = await this.writer.registerChannel({ topic, schemaId, messageEncoding: "cdr", metadata: new Map() });
    this.channels.set(topic, { id, type });
  }
  async write(topic, stamp, message) {
    const { id, type } = this.channels.get(topic);
    const data = this.writers.get(type).writer.writeMessage(message);
    const time = BigInt(stamp.sec) * 1000000000n + BigInt(stamp.nanosec);
    await this.writer.addMessage({ channelId: id, sequence: 0, logTime: time, publishTime: time, data });
  }
  async close() {
    await this.writer.end();
    fs.writeFileSync(this.file, Buffer.concat(this.parts));
  }
}

// "1000.25" -> {sec: 1000, nanosec: 250000000}, exactly as written.
function stampOf(text) {
  const [whole, fraction = ""] = text.split(".");
  return { sec: Number(whole), nanosec: Number((fraction + "000000000").slice(0, 9)) };
}

function lines(file) {
  return fs.readFileSync(file, "utf8").split("\n").map((l) => l.trim()).filter((l) => l && !l.startsWith("#"))
    .map((l) => l.split(/\s+/));
}

function cameraInfo(stamp, width, height, [fx, fy, cx, cy]) {
  return {
    header: { stamp, frame_id: "camera_depth_optical_frame" }, height, width, distortion_model: "plumb_bob",
    d: [0, 0, 0, 0, 0], k: [fx, 0, cx, 0, fy, cy, 0, 0, 1], r: [1, 0, 0, 0, 1, 0, 0, 0, 1],
    p: [fx, 0, cx, 0, 0, fy, cy, 0, 0, 0, 1, 0], binning_x: 0, binning_y: 0,
    roi: { x_offset: 0, y_offset: 0, height: 0, width: 0, do_rectify: false },
  };
}

function depthImage(stamp, width, height, counts, encoding = "16UC1") {
  const data = new Uint8Array(width * height * 2);
  const view = new DataView(data.buffer);
  for (let i = 0; i < width * height; ++i) view.setUint16(2 * i, counts[i], true);
  return { header: { stamp, frame_id: "camera_depth_optical_frame" }, height, width, encoding, is_bigendian: 0, step: width * 2, data };
}

function transform(stamp, parent, child, [tx, ty, tz, qx, qy, qz, qw]) {
  return { header: { stamp, frame_id: parent }, child_frame_id: child,
    transform: { translation: { x: tx, y: ty, z: tz }, rotation: { x: qx, y: qy, z: qz, w: qw } } };
}

function poseStamped(stamp, [tx, ty, tz, qx, qy, qz, qw]) {
  return { header: { stamp, frame_id: "world" }, pose: { position: { x: tx, y: ty, z: tz }, orientation: { x: qx, y: qy, z: qz, w: qw } } };
}

async function declareTopics(bag) {
  await bag.topic("/tf_static", "tf2_msgs/msg/TFMessage");
  await bag.topic("/tf", "tf2_msgs/msg/TFMessage");
  await bag.topic("/camera/pose", "geometry_msgs/msg/PoseStamped");
  await bag.topic("/camera/depth/camera_info", "sensor_msgs/msg/CameraInfo");
  await bag.topic("/camera/depth/image_raw", "sensor_msgs/msg/Image");
}

// The static transform is the identity: composing the chain then adds no
// rounding, so the tf poses equal the TUM file's bit for bit (the byte
// comparison of tests/cli_bag.sh); non-trivial chains are checked with
// tolerances by the C++ unit tests.
const IDENTITY = [0, 0, 0, 0, 0, 0, 1];

async function writeTum(folder, out, intrinsics, compression) {
  const frames = lines(path.join(folder, "depth.txt"));
  const poses = lines(path.join(folder, "reported.txt"));
  if (poses.length !== frames.length) throw new Error("reported.txt and depth.txt differ in length");
  const bag = new Bag(out, compression);
  await bag.start();
  await declareTopics(bag);
  const first = stampOf(frames[0][0]);
  await bag.write("/tf_static", first, { transforms: [transform(first, "base", "camera_depth_optical_frame", IDENTITY)] });
  for (let i = 0; i < frames.length; ++i) {
    const stamp = stampOf(frames[i][0]);
    const png = pngjs.PNG.sync.read(fs.readFileSync(path.join(folder, frames[i][1])), { skipRescale: true });
    if (png.depth !== 16) throw new Error(`${frames[i][1]}: expected a 16-bit PNG`);
    const channels = png.data.length / (png.width * png.height);
    const counts = new Uint16Array(png.width * png.height);
    for (let p = 0; p < counts.length; ++p) counts[p] = png.data[p * channels];
    const pose = poses[i].slice(1).map(Number);
    await bag.write("/tf", stamp, { transforms: [transform(stamp, "world", "base", pose)] });
    await bag.write("/camera/pose", stamp, poseStamped(stamp, pose));
    await bag.write("/camera/depth/camera_info", stamp, cameraInfo(stamp, png.width, png.height, intrinsics));
    await bag.write("/camera/depth/image_raw", stamp, depthImage(stamp, png.width, png.height, counts));
  }
  await bag.close();
}

// A 4x3 image of a wall 1 m away.
const W = 4, H = 3;
const WALL = new Array(W * H).fill(1000);
const SMALL_CAMERA = [2, 2, 1.5, 1];

async function smallBag(file, { compression = "none", cameraInfo: withInfo = true, encoding = "16UC1", poseStamps = null } = {}) {
  const bag = new Bag(file, compression);
  await bag.start();
  await declareTopics(bag);
  const stamps = [0, 1, 2, 3].map((s) => ({ sec: 100 + s, nanosec: 0 }));
  for (const stamp of poseStamps ?? stamps)
    await bag.write("/camera/pose", stamp, poseStamped(stamp, [0, 0, 0, 0, 0, 0, 1]));
  for (const stamp of stamps) {
    if (withInfo) await bag.write("/camera/depth/camera_info", stamp, cameraInfo(stamp, W, H, SMALL_CAMERA));
    await bag.write("/camera/depth/image_raw", stamp, depthImage(stamp, W, H, WALL, encoding));
  }
  await bag.close();
}

async function writeErrorBags(dir) {
  fs.mkdirSync(dir, { recursive: true });
  await smallBag(path.join(dir, "good.mcap"));
  await smallBag(path.join(dir, "good_zstd.mcap"), { compression: "zstd" });
  await smallBag(path.join(dir, "good_lz4.mcap"), { compression: "lz4" });
  await smallBag(path.join(dir, "missing_camera_info.mcap"), { cameraInfo: false });
  await smallBag(path.join(dir, "rgb8.mcap"), { encoding: "rgb8" });
  // Poses at 100 s and 103 s only: the images at 101 s and 102 s have none near.
  await smallBag(path.join(dir, "pose_gap.mcap"), { poseStamps: [{ sec: 100, nanosec: 0 }, { sec: 103, nanosec: 0 }] });
  // The writer computes the CRC of the records it is given; one byte changed
  // afterwards, stored uncompressed, no longer matches it.
  await smallBag(path.join(dir, "bad_crc.mcap"), {
    compression: (data) => {
      const changed = Uint8Array.from(data);
      changed[changed.length - 1] ^= 0xff;
      return { compression: "", compressedData: changed };
    },
  });
  // Declared zstd, holding bytes no zstd decoder accepts.
  await smallBag(path.join(dir, "bad_zstd.mcap"), {
    compression: (data) => ({ compression: "zstd", compressedData: new Uint8Array(64).fill(0x5a) }),
  });
}

async function main() {
  const [mode, ...args] = process.argv.slice(2);
  await zstd.isLoaded;
  if (mode === "tum") {
    const [folder, out, ...rest] = args;
    const option = (name, fallback) => { const i = rest.indexOf(name); return i >= 0 ? rest[i + 1] : fallback; };
    const intrinsics = option("--intrinsics", "").split(",").map(Number);
    if (intrinsics.length !== 4 || intrinsics.some((v) => !Number.isFinite(v))) throw new Error("--intrinsics fx,fy,cx,cy");
    await writeTum(folder, out, intrinsics, option("--compression", "zstd"));
  } else if (mode === "errors") {
    await writeErrorBags(args[0]);
  } else {
    throw new Error("usage: write_bag.mjs tum FOLDER OUT.mcap --intrinsics fx,fy,cx,cy [--compression zstd|lz4|none] | errors DIR");
  }
}

main().catch((error) => { console.error(`write_bag.mjs: ${error.message}`); process.exit(1); });
