#include "input/mcap/ros_messages.hpp"

namespace icrkit::reconstruction::mcap {
namespace {

RosTransform readTransform(CdrReader& cdr) {
  RosTransform transform;
  for (double& v : transform.translation) v = cdr.float64();
  for (double& v : transform.rotation_xyzw) v = cdr.float64();
  return transform;
}

}  // namespace

double RosTime::seconds() const {
  // Division keeps whole-second stamps exact and others correctly rounded.
  return static_cast<double>(sec) + static_cast<double>(nanosec) / 1e9;
}

RosHeader readHeader(CdrReader& cdr) {
  RosHeader header;
  header.stamp.sec = cdr.int32();
  header.stamp.nanosec = cdr.uint32();
  header.frame_id = cdr.string();
  return header;
}

RosImage readImageHeader(CdrReader& cdr) {
  RosImage image;
  image.header = readHeader(cdr);
  image.height = cdr.uint32();
  image.width = cdr.uint32();
  image.encoding = cdr.string();
  return image;
}

RosImage readImage(CdrReader& cdr) {
  RosImage image = readImageHeader(cdr);
  image.is_bigendian = cdr.uint8() != 0;
  image.step = cdr.uint32();
  image.data_size = cdr.sequenceLength(1);
  image.data = cdr.bytes(image.data_size);
  if (static_cast<std::uint64_t>(image.step) * image.height > image.data_size)
    cdr.fail("the image holds " + std::to_string(image.data_size) + " bytes, fewer than step " +
             std::to_string(image.step) + " x height " + std::to_string(image.height));
  return image;
}

RosCameraInfo readCameraInfo(CdrReader& cdr) {
  RosCameraInfo info;
  info.header = readHeader(cdr);
  info.height = cdr.uint32();
  info.width = cdr.uint32();
  info.distortion_model = cdr.string();
  const std::uint32_t count = cdr.sequenceLength(8);
  info.d.resize(count);
  for (double& v : info.d) v = cdr.float64();
  for (double& v : info.k) v = cdr.float64();
  return info;
}

RosPoseStamped readPoseStamped(CdrReader& cdr) {
  RosPoseStamped pose;
  pose.header = readHeader(cdr);
  pose.pose = readTransform(cdr);
  return pose;
}

std::vector<RosTransformStamped> readTfMessage(CdrReader& cdr) {
  // Each element holds at least a header, a frame id and 7 doubles.
  const std::uint32_t count = cdr.sequenceLength(4 + 4 + 4 + 4 + 7 * 8);
  std::vector<RosTransformStamped> transforms(count);
  for (RosTransformStamped& t : transforms) {
    t.header = readHeader(cdr);
    t.child_frame_id = cdr.string();
    t.transform = readTransform(cdr);
  }
  return transforms;
}

}  // namespace icrkit::reconstruction::mcap
