// SPDX-License-Identifier: MIT
/// @brief The xArm controller's private TCP protocol on its command port (UFACTORY's developer
///        manual, "communication format"; written from the public description, robot/xarm/README.md):
///        Modbus-TCP-style frames
///          request:  [transaction U16 BE][protocol U16 BE = 2][length U16 BE][register U8][params]
///          response: [transaction U16 BE][protocol U16 BE][length U16 BE][register U8][status U8][params]
///        where length counts the bytes after the length field. FP32 parameters are little endian,
///        U16 data big endian. The response status byte says whether the controller has an error
///        (bit 6), a warning (bit 5), is not ready to move (bit 4) or did not carry the command out
///        (bit 3). The registers this project uses, the controller's states and modes.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace telesphere::xarm {

constexpr int kCommandPort = 502;
constexpr int kRealtimeReportPort = 30003;  ///< 100 Hz joint positions (87-byte reports)
constexpr std::uint16_t kPrivateProtocol = 2;
/// Longest frame either side sends here (get version: 6 + 2 + 40 bytes); longer ones are refused as
/// malformed before anything is allocated.
constexpr std::size_t kMaxFrameBytes = 512;

enum class Register : std::uint8_t {
  kGetVersion = 1,
  kMotionEnable = 11,  ///< params: joint (8 = all), enable (1/0)
  kSetState = 12,      ///< params: ControllerState (0 = start motion, 3 pause, 4 stop)
  kGetState = 13,      ///< reply: ControllerState
  kGetCmdNum = 14,     ///< reply: U16 BE, commands buffered
  kGetErrorWarning = 15,  ///< reply: error code U8, warning code U8
  kCleanError = 16,
  kCleanWarning = 17,
  kSetMode = 19,        ///< params: ControllerMode
  kMoveJoint = 23,      ///< params: 7 joints, speed, acc, mvtime (FP32 LE; rad, rad/s, rad/s², s)
  kMoveServoJoint = 29, ///< params: 7 joints + 3 ignored (FP32 LE, rad)
  kGetJointPositions = 42,  ///< reply: 7 × FP32 LE, rad
};

/// What the controller reports in the state nibble and register 13.
enum class ControllerState : std::uint8_t {
  kStart = 0,        ///< as a request: enter motion (ready) state
  kMoving = 1,
  kReady = 2,        ///< "sleeping": waiting for commands
  kPaused = 3,
  kStopped = 4,      ///< after a stop request, an error or an emergency stop
  kModeChanged = 5,  ///< after enable/mode change: needs set state 0 before it moves
  kDecelerating = 6,
};

enum class ControllerMode : std::uint8_t {
  kPosition = 0,  ///< the controller plans (move joint, queued)
  kServo = 1,     ///< servo joint targets, executed at once, the newest wins
  kJointTeaching = 2,
};

/// Response status bits.
constexpr std::uint8_t kStatusError = 0x40;
constexpr std::uint8_t kStatusWarning = 0x20;
constexpr std::uint8_t kStatusNotReady = 0x10;
constexpr std::uint8_t kStatusFailed = 0x08;

struct Frame {
  std::uint16_t transaction = 0;
  std::uint16_t protocol = kPrivateProtocol;
  std::uint8_t reg = 0;
  /// Bytes after the register: a response's status byte first, then its parameters.
  std::vector<std::uint8_t> body;

  /// Response status (0 when the body is empty).
  std::uint8_t status() const { return body.empty() ? 0 : body[0]; }
  /// A response's parameters (after the status byte).
  std::span<const std::uint8_t> replyParams() const {
    return body.empty() ? std::span<const std::uint8_t>() : std::span<const std::uint8_t>(body).subspan(1);
  }
};

std::vector<std::uint8_t> encodeRequest(std::uint16_t transaction, Register reg, std::span<const std::uint8_t> params);
std::vector<std::uint8_t> encodeResponse(std::uint16_t transaction, std::uint8_t reg, std::uint8_t status,
                                         std::span<const std::uint8_t> params);

/// Reassembles frames from a TCP byte stream, either direction. Once it has seen a malformed header
/// (a protocol id other than 0, 2 or 3, a length of 0 or beyond kMaxFrameBytes) the stream cannot
/// be resynchronised: failed() stays true and error() says why.
class FrameReader {
 public:
  void feed(std::span<const std::uint8_t> bytes);
  /// The next complete frame, if one is buffered (nothing after a failure).
  std::optional<Frame> next();
  bool failed() const { return !error_.empty(); }
  const std::string& error() const { return error_; }
  std::size_t buffered() const { return buffer_.size(); }

 private:
  std::vector<std::uint8_t> buffer_;
  std::string error_;
};

// Parameter encoding (FP32 little endian, U16 big endian), as the protocol fixes them.
void appendF32(std::vector<std::uint8_t>& out, float value);
float readF32(std::span<const std::uint8_t> in, std::size_t offset);
void appendU16(std::vector<std::uint8_t>& out, std::uint16_t value);
std::uint16_t readU16(std::span<const std::uint8_t> in, std::size_t offset);
void appendU32(std::vector<std::uint8_t>& out, std::uint32_t value);
std::uint32_t readU32(std::span<const std::uint8_t> in, std::size_t offset);

/// Register 29's parameters: the six joints (rad), J7 = 0, and the three ignored values (0).
std::vector<std::uint8_t> servoJointParams(const std::array<double, 6>& q);
/// Register 23's parameters: the six joints (rad), J7 = 0, speed (rad/s), acceleration (rad/s²), mvtime 0.
std::vector<std::uint8_t> moveJointParams(const std::array<double, 6>& q, double speed, double acceleration);
/// The six joints of a register 23 or 29 request (nothing when it is too short).
std::optional<std::array<double, 6>> jointsOfMoveParams(std::span<const std::uint8_t> params);

std::string registerName(std::uint8_t reg);
std::string stateName(std::uint8_t state);
std::string modeName(std::uint8_t mode);

}  // namespace telesphere::xarm
