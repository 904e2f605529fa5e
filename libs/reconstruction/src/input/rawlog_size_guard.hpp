#pragma once
// MRPT's deserializer allocates a range image (CObservation3DRangeScan,
// rows x cols) or a matrix (CMatrixF/CMatrixD) as soon as it has read the
// two sizes from the stream, before any pixel; for a corrupt size its
// aligned allocator returns null and MRPT writes through it (a crash, not
// an exception; found by the rawlog fuzz target, docs/reliability.md).
// This stream sits between the file and MRPT's archive and watches the
// bytes as MRPT reads them: on the object headers of those classes it
// follows their layout (MRPT 2.5's, versions 8-10 of the range scan)
// to the sizes and refuses, by throwing before MRPT gets them, a range
// image or matrix beyond `max_elements` or a point count beyond it. A
// camera's intrinsics (TCamera, versions 5-6) end with its name, a string
// MRPT sizes from its stored length before reading it (a corrupt length:
// gigabytes for a 2 MB file, found by the fuzz target): refused beyond
// `kMaxCameraName` bytes. After a range scan's second camera (the
// intensity camera) it follows the scan's tail the same way: the strings
// MRPT sizes before reading them (the sensor label, the external file
// names, the extra layers' names) are refused beyond `kMaxString` bytes and
// an extra range layer beyond `max_elements`. It changes no byte; layouts
// it does not know it leaves to MRPT.

#include <mrpt/io/CStream.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace icrkit::reconstruction {

class RawlogSizeGuard : public mrpt::io::CStream {
 public:
  /// A camera name longer than this (bytes) is corrupt.
  static constexpr std::uint32_t kMaxCameraName = 4096;
  /// A sensor label, file name or layer name longer than this is corrupt.
  static constexpr std::uint32_t kMaxString = 4096;

  RawlogSizeGuard(mrpt::io::CStream& inner, std::uint64_t max_elements);

  size_t Read(void* buffer, size_t count) override;
  size_t Write(const void* buffer, size_t count) override;
  uint64_t Seek(int64_t offset, CStream::TSeekOrigin origin = sFromBeginning) override;
  uint64_t getTotalBytesCount() const override;
  uint64_t getPosition() const override;

  /// Why the last read was refused (empty if none): MRPT may wrap the
  /// exception thrown through it, so the reader asks here.
  const std::string& refusal() const { return refusal_; }

 private:
  enum class State {
    Idle,             // looking for an object header
    ScanVersion,      // CObservation3DRangeScan: version byte
    ScanMaxRange,     // float
    ScanPoseHeader,   // a CPose3D object header
    ScanPoseVersion,  // its version (2: seven doubles, 3: twelve)
    ScanPoseData,
    ScanPoseEnd,      // the end-of-object flag
    ScanHasPoints,    // bool
    ScanPointCount,   // uint32
    ScanPoints,       // skipped
    ScanHasRange,     // bool
    ScanRangeUnits,   // float (version >= 9)
    ScanRows,         // uint32
    ScanCols,         // uint32: refused here when too large
    MatrixVersion,    // CMatrixF / CMatrixD
    MatrixRows,
    MatrixCols,
    CameraVersion,    // TCamera
    CameraFields,     // skipped: focal length, distortion, intrinsics, size
    CameraNameLength, // uint32: refused here when too large
    CameraName,       // skipped (and version 6's distortion model byte)
    CameraEnd,        // the end-of-object flag
    // A range scan's tail, after its intensity camera (versions 8-10):
    TailPoseHeader,   // relativePoseIntensityWRTDepth, a CPose3D object
    TailPoseVersion,
    TailPoseData,
    TailPoseEnd,
    TailErrorAndStamp,  // float, uint64
    TailStringLength,   // uint32: refused here when too large
    TailStringBytes,    // skipped
    TailFixed,          // `tail_need_` bytes of flags or sizes
    TailSkip            // an extra range layer's pixels, skipped
  };
  // The fields of a range scan's tail after its timestamp, in stream order
  // (tailFieldDone steps to the next by value).
  enum class TailStep {
    Label,               // string
    PointsFlag,          // bool: points stored in an external file
    PointsFile,          // string
    RangeFlag,           // bool: range image stored in an external file
    RangeFile,           // string
    DepthChannelLabels,  // bool, int8, bool: pixel labels follow (not followed)
    LayerCount,          // uint8 (version 10)
    LayerName,           // string
    LayerSize,           // uint32 cols, uint32 rows: refused when too large
    LayerData            // uint16 pixels
  };

  void consume(const std::uint8_t* data, std::size_t n);
  void idleByte(std::uint8_t byte);
  // Collects `need` bytes of a field; true once complete (in field_).
  bool collect(const std::uint8_t*& data, std::size_t& n, std::size_t need);
  // Passes over up to `skip_` bytes; true once all of them are behind.
  bool skipped(const std::uint8_t*& data, std::size_t& n);
  std::uint32_t fieldU32() const;
  void refuse(const std::string& what);
  // Starts reading the tail's field `step`.
  void enterTail(TailStep step);
  // The current tail field is complete (its bytes in field_ if fixed).
  void tailFieldDone();
  // Back to looking for headers.
  void leaveTail();

  mrpt::io::CStream& inner_;
  std::uint64_t max_elements_;
  State state_ = State::Idle;
  std::array<std::uint8_t, 48> recent_{};  // the last bytes seen while idle (ring)
  std::size_t recent_count_ = 0;
  std::string field_;
  std::uint8_t version_ = 0;
  std::uint8_t camera_version_ = 0;
  // TCamera headers seen since the last range scan's header (-1: not in a
  // range scan whose tail this follows).
  int scan_cameras_ = -1;
  TailStep tail_step_ = TailStep::Label;
  std::size_t tail_need_ = 0;
  std::uint32_t layers_left_ = 0;
  std::size_t pose_bytes_ = 0;
  bool has_range_ = false;
  std::uint32_t rows_ = 0;
  std::uint64_t skip_ = 0;
  std::string refusal_;
};

}  // namespace icrkit::reconstruction
