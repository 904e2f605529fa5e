#include "rawlog_size_guard.hpp"

#include <algorithm>
#include <iterator>
#include <cstring>
#include <stdexcept>

namespace icrkit::reconstruction {

namespace {

// MRPT's object header: one byte 0x80 | length, the class name (with its
// namespace since MRPT 2, without before), a version byte.
std::string header(const std::string& name) { return std::string(1, char(0x80 | name.size())) + name; }
const std::string kScanHeaders[] = {header("mrpt::obs::CObservation3DRangeScan"), header("CObservation3DRangeScan")};
const std::string kMatrixHeaders[] = {header("mrpt::math::CMatrixF"), header("mrpt::math::CMatrixD"),
                                      header("CMatrixF"), header("CMatrixD")};
const std::string kCameraHeaders[] = {header("mrpt::img::TCamera"), header("TCamera")};
const std::string kPoseNames[] = {"mrpt::poses::CPose3D", "CPose3D"};
// TCamera (versions 4-6) before its name: the focal length, eight
// distortion coefficients and fx, fy, cx, cy (doubles), rows and columns
// (uint32).
constexpr std::size_t kCameraFieldBytes = 8 + 8 * 8 + 4 * 8 + 2 * 4;
constexpr std::uint8_t kEndOfObject = 0x88;

// CPose3D's stored size per version: 2, seven doubles (position and
// quaternion); 3, twelve (position and rotation matrix).
std::size_t poseBytes(std::uint8_t version) { return version == 2 ? 56 : version == 3 ? 96 : 0; }

}  // namespace

RawlogSizeGuard::RawlogSizeGuard(mrpt::io::CStream& inner, std::uint64_t max_elements)
    : inner_(inner), max_elements_(max_elements) {}

size_t RawlogSizeGuard::Read(void* buffer, size_t count) {
  const size_t got = inner_.Read(buffer, count);
  // A failed gzip read reports (size_t)-1: nothing was read.
  if (got <= count) consume(static_cast<const std::uint8_t*>(buffer), got);
  return got;
}

size_t RawlogSizeGuard::Write(const void*, size_t) { throw std::logic_error("RawlogSizeGuard is read-only"); }

uint64_t RawlogSizeGuard::Seek(int64_t offset, CStream::TSeekOrigin origin) {
  // A jump breaks the layout being followed: start over from the next header.
  state_ = State::Idle;
  recent_count_ = 0;
  scan_cameras_ = -1;
  return inner_.Seek(offset, origin);
}

uint64_t RawlogSizeGuard::getTotalBytesCount() const { return inner_.getTotalBytesCount(); }
uint64_t RawlogSizeGuard::getPosition() const { return inner_.getPosition(); }

void RawlogSizeGuard::refuse(const std::string& what) {
  refusal_ = what + " at byte " + std::to_string(inner_.getPosition()) +
             " (uncompressed): beyond any depth camera, the file is corrupt";
  state_ = State::Idle;
  throw std::runtime_error(refusal_);
}

std::uint32_t RawlogSizeGuard::fieldU32() const {
  // MRPT writes little endian.
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = (v << 8) | static_cast<std::uint8_t>(field_[static_cast<std::size_t>(k)]);
  return v;
}

bool RawlogSizeGuard::collect(const std::uint8_t*& data, std::size_t& n, std::size_t need) {
  const std::size_t take = std::min(n, need - field_.size());
  field_.append(reinterpret_cast<const char*>(data), take);
  data += take;
  n -= take;
  return field_.size() == need;
}

bool RawlogSizeGuard::skipped(const std::uint8_t*& data, std::size_t& n) {
  const std::uint64_t take = std::min<std::uint64_t>(skip_, n);
  data += take;
  n -= static_cast<std::size_t>(take);
  skip_ -= take;
  return skip_ == 0;
}

void RawlogSizeGuard::idleByte(std::uint8_t byte) {
  recent_[recent_count_ % recent_.size()] = byte;
  ++recent_count_;
  // Cheap first test: the last letter of one of the class names.
  if (byte != 'n' && byte != 'F' && byte != 'D' && byte != 'a') return;
  auto endsWith = [&](const std::string& header) {
    if (recent_count_ < header.size()) return false;
    for (std::size_t k = 0; k < header.size(); ++k) {
      const std::size_t at = (recent_count_ - header.size() + k) % recent_.size();
      if (recent_[at] != static_cast<std::uint8_t>(header[k])) return false;
    }
    return true;
  };
  if (byte == 'n') {
    for (const std::string& h : kScanHeaders)
      if (endsWith(h)) state_ = State::ScanVersion;
  } else if (byte == 'a') {
    for (const std::string& h : kCameraHeaders)
      if (endsWith(h)) {
        state_ = State::CameraVersion;
        if (scan_cameras_ >= 0) ++scan_cameras_;
      }
  } else {
    for (const std::string& h : kMatrixHeaders)
      if (endsWith(h)) state_ = State::MatrixVersion;
  }
  if (state_ != State::Idle) {
    recent_count_ = 0;
    field_.clear();
  }
}

void RawlogSizeGuard::consume(const std::uint8_t* data, std::size_t n) {
  while (n > 0) {
    switch (state_) {
      case State::Idle:
        idleByte(*data++);
        --n;
        break;
      case State::ScanVersion:
        version_ = *data++;
        --n;
        // Versions 9 and 10 store the range image's sizes right after the
        // points (older ones store a CMatrixF, caught by its own header).
        state_ = version_ >= 8 && version_ <= 10 ? State::ScanMaxRange : State::Idle;
        scan_cameras_ = state_ == State::Idle ? -1 : 0;
        break;
      case State::ScanMaxRange:
        if (collect(data, n, 4)) {
          field_.clear();
          state_ = State::ScanPoseHeader;
        }
        break;
      case State::ScanPoseHeader:
      case State::TailPoseHeader: {
        const bool tail = state_ == State::TailPoseHeader;
        // The length byte, then that many bytes of class name (a read may
        // end between them: the length byte is collected only once).
        if (field_.empty() && !collect(data, n, 1)) break;
        const auto length = static_cast<std::uint8_t>(field_[0]);
        if (!(length & 0x80)) {
          state_ = State::Idle;
          field_.clear();
          break;
        }
        if (collect(data, n, 1 + (length & 0x7F))) {
          const std::string name = field_.substr(1);
          state_ = std::find(std::begin(kPoseNames), std::end(kPoseNames), name) != std::end(kPoseNames)
                       ? (tail ? State::TailPoseVersion : State::ScanPoseVersion)
                       : State::Idle;
          field_.clear();
        }
        break;
      }
      case State::ScanPoseVersion:
      case State::TailPoseVersion:
        pose_bytes_ = poseBytes(*data);
        state_ = pose_bytes_ == 0                         ? State::Idle
                 : state_ == State::ScanPoseVersion ? State::ScanPoseData
                                                    : State::TailPoseData;
        ++data;
        --n;
        break;
      case State::ScanPoseData:
      case State::TailPoseData:
        if (collect(data, n, pose_bytes_)) {
          field_.clear();
          state_ = state_ == State::ScanPoseData ? State::ScanPoseEnd : State::TailPoseEnd;
        }
        break;
      case State::ScanPoseEnd:
      case State::TailPoseEnd:
        state_ = *data != kEndOfObject            ? State::Idle
                 : state_ == State::ScanPoseEnd ? State::ScanHasPoints
                                                : State::TailErrorAndStamp;
        ++data;
        --n;
        break;
      case State::ScanHasPoints:
        state_ = *data ? State::ScanPointCount : State::ScanHasRange;
        ++data;
        --n;
        break;
      case State::ScanPointCount:
        if (collect(data, n, 4)) {
          const std::uint64_t points = fieldU32();
          field_.clear();
          if (points > max_elements_)
            refuse("a 3D scan with " + std::to_string(points) + " points (at most " + std::to_string(max_elements_) +
                   " accepted)");
          // x, y, z floats, then (version >= 8) the pixel columns and rows as uint16.
          skip_ = points * (3 * 4 + 2 * 2);
          state_ = State::ScanPoints;
        }
        break;
      case State::ScanPoints:
        if (skipped(data, n)) state_ = State::ScanHasRange;
        break;
      case State::ScanHasRange:
        has_range_ = *data != 0;
        ++data;
        --n;
        state_ = version_ >= 9 ? State::ScanRangeUnits : State::Idle;
        break;
      case State::ScanRangeUnits:
        if (collect(data, n, 4)) {
          field_.clear();
          state_ = has_range_ ? State::ScanRows : State::Idle;
        }
        break;
      case State::ScanRows:
      case State::MatrixRows:
        if (collect(data, n, 4)) {
          rows_ = fieldU32();
          field_.clear();
          state_ = state_ == State::ScanRows ? State::ScanCols : State::MatrixCols;
        }
        break;
      case State::ScanCols:
      case State::MatrixCols:
        if (collect(data, n, 4)) {
          const std::uint64_t cols = fieldU32();
          const bool scan = state_ == State::ScanCols;
          field_.clear();
          state_ = State::Idle;
          if (std::uint64_t(rows_) * cols > max_elements_)
            refuse(std::string(scan ? "a range image" : "a matrix") + " of " + std::to_string(rows_) + " x " +
                   std::to_string(cols) + " elements (at most " + std::to_string(max_elements_) + " accepted)");
        }
        break;
      case State::MatrixVersion:
        state_ = *data == 0 ? State::MatrixRows : State::Idle;
        ++data;
        --n;
        break;
      case State::CameraVersion:
        // The name is stored from version 5 on.
        camera_version_ = *data;
        state_ = camera_version_ >= 5 && camera_version_ <= 6 ? State::CameraFields : State::Idle;
        if (state_ == State::Idle) scan_cameras_ = -1;
        skip_ = kCameraFieldBytes;
        ++data;
        --n;
        break;
      case State::CameraFields:
        if (skipped(data, n)) state_ = State::CameraNameLength;
        break;
      case State::CameraNameLength:
        if (collect(data, n, 4)) {
          const std::uint32_t length = fieldU32();
          field_.clear();
          state_ = State::Idle;
          if (length > kMaxCameraName)
            refuse("a camera name of " + std::to_string(length) + " bytes (at most " +
                   std::to_string(kMaxCameraName) + " accepted)");
          // Version 6 ends with the distortion model (a byte).
          skip_ = std::uint64_t{length} + (camera_version_ == 6 ? 1 : 0);
          state_ = State::CameraName;
        }
        break;
      case State::CameraName:
        if (skipped(data, n)) state_ = State::CameraEnd;
        break;
      case State::CameraEnd: {
        const bool ended = *data == kEndOfObject;
        ++data;
        --n;
        // A range scan's second camera (its intensity camera) is followed
        // by the scan's tail.
        state_ = ended && scan_cameras_ == 2 ? State::TailPoseHeader : State::Idle;
        if (!ended || scan_cameras_ >= 2) scan_cameras_ = -1;
        break;
      }
      case State::TailErrorAndStamp:
        if (collect(data, n, 4 + 8)) {
          field_.clear();
          enterTail(TailStep::Label);
        }
        break;
      case State::TailStringLength:
        if (collect(data, n, 4)) {
          const std::uint32_t length = fieldU32();
          field_.clear();
          if (length > kMaxString) {
            const char* what = tail_step_ == TailStep::Label       ? "a sensor label"
                               : tail_step_ == TailStep::LayerName ? "a range layer name"
                                                                   : "an external file name";
            refuse(std::string(what) + " of " + std::to_string(length) + " bytes (at most " +
                   std::to_string(kMaxString) + " accepted)");
          }
          skip_ = length;
          state_ = State::TailStringBytes;
        }
        break;
      case State::TailStringBytes:
        if (skipped(data, n)) tailFieldDone();
        break;
      case State::TailFixed:
        if (collect(data, n, tail_need_)) tailFieldDone();
        break;
      case State::TailSkip:
        if (skipped(data, n)) tailFieldDone();
        break;
    }
  }
}

void RawlogSizeGuard::enterTail(TailStep step) {
  tail_step_ = step;
  field_.clear();
  switch (step) {
    case TailStep::Label:
    case TailStep::PointsFile:
    case TailStep::RangeFile:
    case TailStep::LayerName:
      state_ = State::TailStringLength;
      return;
    case TailStep::LayerData:
      state_ = State::TailSkip;  // skip_ set by LayerSize
      return;
    default:
      // Flags and sizes: their bytes.
      tail_need_ = step == TailStep::DepthChannelLabels ? 3 : step == TailStep::LayerSize ? 8 : 1;
      state_ = State::TailFixed;
  }
}

void RawlogSizeGuard::leaveTail() {
  field_.clear();
  state_ = State::Idle;
}

void RawlogSizeGuard::tailFieldDone() {
  switch (tail_step_) {
    case TailStep::DepthChannelLabels:
      // Pixel labels have a layout of their own: left to MRPT, as is a
      // version without extra layers.
      if (field_[2] != 0 || version_ < 10)
        leaveTail();
      else
        enterTail(TailStep::LayerCount);
      return;
    case TailStep::LayerCount:
      layers_left_ = static_cast<std::uint8_t>(field_[0]);
      if (layers_left_ == 0)
        leaveTail();
      else
        enterTail(TailStep::LayerName);
      return;
    case TailStep::LayerSize: {
      const std::uint64_t first = fieldU32();
      field_.erase(0, 4);
      const std::uint64_t second = fieldU32();
      field_.clear();
      if (first * second > max_elements_)
        refuse("a range layer of " + std::to_string(first) + " x " + std::to_string(second) + " elements (at most " +
               std::to_string(max_elements_) + " accepted)");
      skip_ = first * second * 2;
      enterTail(TailStep::LayerData);
      return;
    }
    case TailStep::LayerData:
      if (--layers_left_ > 0)
        enterTail(TailStep::LayerName);
      else
        leaveTail();
      return;
    default:
      // The other fields are followed by the next in stream order.
      enterTail(static_cast<TailStep>(static_cast<int>(tail_step_) + 1));
  }
}

}  // namespace icrkit::reconstruction
