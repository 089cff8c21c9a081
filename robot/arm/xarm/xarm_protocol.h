// SPDX-License-Identifier: MIT
/// @brief The xArm controller's private TCP protocol on its command port (UFACTORY's developer
///        manual, "communication format"; written from the public description, robot/arm/xarm/README.md):
///        Modbus-TCP-style frames
///          request:  [transaction U16 BE][protocol U16 BE][length U16 BE][register U8][params]
///          response: [transaction U16 BE][protocol U16 BE][length U16 BE][register U8][status U8][params]
///        where length counts the bytes after the length field. FP32 parameters are little endian,
///        U16 data big endian. The response status byte says whether the controller has an error
///        (bit 6), a warning (bit 5), is not ready to move (bit 4) or did not carry the command out
///        (bit 3). The registers this project uses, the controller's states and modes.
///
///        Protocol identifier: 2, the private protocol; firmware 1.8.6 and later also speaks 3, the
///        private protocol "with heartbeat", which UFACTORY's own clients switch to after reading
///        the version (register 1). A reply carries the identifier of its request, as it carries
///        its transaction and register. Identifier 1 is the old 8-byte heartbeat frame some
///        clients send every second; it has no reply. robot/arm/xarm/README.md has the sources.
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
constexpr int kNormalReportPort = 30001;    ///< 5 Hz, 145 bytes: with error, payload and sensitivities
constexpr std::uint16_t kHeartbeatProtocol = 1;              ///< the old heartbeat frame (no reply)
constexpr std::uint16_t kPrivateProtocol = 2;
constexpr std::uint16_t kPrivateProtocolWithHeartbeat = 3;   ///< firmware ≥ 1.8.6
/// Longest frame either side sends here (get version: 6 + 2 + 40 bytes); longer ones are refused as
/// malformed before anything is allocated.
constexpr std::size_t kMaxFrameBytes = 512;

enum class Register : std::uint8_t {
  kGetVersion = 1,     ///< reply: 40 bytes ASCII "axis,type,armSN,boxSN,vX.Y.Z", NUL-padded
  kGetRobotSn = 2,     ///< reply: 40 bytes: the arm's serial, NUL, the control box's serial, padding
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
  kSetTcpLoad = 36,     ///< params: mass (kg), centre of mass x, y, z (mm, tool frame), FP32 LE
  kSetCollisionSensitivity = 37,  ///< params: U8 0..5 (0: off); a "system reset": stopped, set state 0 after
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

std::vector<std::uint8_t> encodeRequest(std::uint16_t transaction, Register reg, std::span<const std::uint8_t> params,
                                        std::uint16_t protocol = kPrivateProtocol);
/// `protocol`: the request's (the controller echoes it).
std::vector<std::uint8_t> encodeResponse(std::uint16_t transaction, std::uint8_t reg, std::uint8_t status,
                                         std::span<const std::uint8_t> params, std::uint16_t protocol = kPrivateProtocol);

/// Reassembles frames from a TCP byte stream, either direction. Once it has seen a malformed header
/// (a protocol id other than 0..3, a length of 0 or beyond kMaxFrameBytes) the stream cannot
/// be resynchronised: failed() stays true and error() says why. An identifier-1 heartbeat frame
/// comes out as a frame with protocol 1 (its "register" byte is 0).
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

/// Register 1's text, parsed as UFACTORY's clients parse it: "axis,type,armSN,boxSN,vX.Y.Z"
/// (older firmware may say less; then only the version is known, or nothing).
struct FirmwareVersion {
  int axis = 0, type = 0;
  std::string arm_sn, box_sn;  ///< 6 characters each ("XI1202", "AC1302")
  int major = 0, minor = 0, patch = 0;
  bool atLeast(int ma, int mi, int pa) const;
  /// The identifier UFACTORY's clients use with this firmware: 3 from 1.8.6 on, else 2.
  std::uint16_t protocol() const { return atLeast(1, 8, 6) ? kPrivateProtocolWithHeartbeat : kPrivateProtocol; }
};
std::optional<FirmwareVersion> parseFirmwareVersion(std::span<const std::uint8_t> register1_reply);
/// Register 2's reply: the arm's serial number (14 characters, "XI120204201B02"), empty if none.
std::string armSerialOfReply(std::span<const std::uint8_t> register2_reply);

/// Register 36's parameters: payload mass (kg) and centre of mass (mm, tool frame).
std::vector<std::uint8_t> tcpLoadParams(double mass_kg, const std::array<double, 3>& com_mm);

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
