// SPDX-License-Identifier: MIT
/// @brief The xArm controller's real-time report (port 30003, pushed at 100 Hz without a request):
///          [length U32 BE = 87 (135 with force/torque data)][state | mode << 4 U8][commands U16 BE]
///          [7 joints FP32 LE, rad][tool pose 6 × FP32 LE, mm and rad][7 joint torques FP32 LE]
///          ([12 × FP32 force/torque])
///        It carries no time stamp and no error code: the time is our arrival time (see
///        XArmHeadArm), the error comes with every command reply's status and from register 15.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace telesphere::xarm {

constexpr std::size_t kRealtimeReportBytes = 87;
constexpr std::size_t kRealtimeReportWithForceBytes = 135;

struct RealtimeReport {
  std::uint8_t state = 0;   ///< ControllerState (low nibble)
  std::uint8_t mode = 0;    ///< ControllerMode (high nibble)
  std::uint16_t commands = 0;
  std::array<double, 7> q{};      ///< rad (J7 unused on an xArm 6)
  std::array<double, 6> tool{};   ///< x, y, z (mm), roll, pitch, yaw (rad)
  std::array<double, 7> torque{}; ///< N·m (or A, as register 70 chose)
};

/// The 87-byte report (what the protocol simulator sends).
std::vector<std::uint8_t> encodeRealtimeReport(const RealtimeReport& report);

/// The "normal" report on port 30001 (5 Hz, 145 bytes; some firmware writes 133 in its length
/// field while sending 145): the real-time report's 87 bytes, then (0-based offsets)
///   87 brake bits U8, 88 enable bits U8, 89 error code U8, 90 warning code U8,
///   91 TCP offset 6 × FP32 (mm, rad), 115 payload mass FP32 (kg), 119 its centre of mass
///   3 × FP32 (mm), 131 collision sensitivity U8 (0..5), 132 teach sensitivity U8,
///   133 gravity direction 3 × FP32.
/// The one place the controller says which payload and collision sensitivity it uses.
constexpr std::size_t kNormalReportBytes = 145;
constexpr std::size_t kNormalReportLegacyLength = 133;

struct NormalReport {
  RealtimeReport realtime;
  std::uint8_t brakes = 0, enabled = 0, error = 0, warning = 0;
  std::array<double, 6> tcp_offset{};
  double payload_kg = 0;
  std::array<double, 3> payload_com_mm{};
  std::uint8_t collision_sensitivity = 0, teach_sensitivity = 0;
  std::array<double, 3> gravity{};
};

std::vector<std::uint8_t> encodeNormalReport(const NormalReport& report);

/// Reassembles normal reports from port 30001's stream; a length field other than 145 (or 133),
/// a change of it, a sensitivity outside 0..5, a state or mode the protocol lacks, fail it.
class NormalReportReader {
 public:
  void feed(std::span<const std::uint8_t> bytes);
  std::optional<NormalReport> next();
  bool failed() const { return !error_.empty(); }
  const std::string& error() const { return error_; }

 private:
  std::vector<std::uint8_t> buffer_;
  std::uint32_t length_field_ = 0;  ///< of the first report
  std::string error_;
};

/// Reassembles reports from the report port's byte stream: each starts with its own length,
/// which must be 87 or 135 and stay the same across the stream (the SDK checks this too); a
/// report that breaks either rule fails the stream (it cannot be resynchronised). A report with
/// a state or mode value the protocol does not have (state > 6, mode > 11) or a joint that is
/// not finite fails it too.
class ReportReader {
 public:
  void feed(std::span<const std::uint8_t> bytes);
  std::optional<RealtimeReport> next();
  bool failed() const { return !error_.empty(); }
  const std::string& error() const { return error_; }

 private:
  std::vector<std::uint8_t> buffer_;
  std::uint32_t length_ = 0;  ///< of the first report
  std::string error_;
};

}  // namespace telesphere::xarm
