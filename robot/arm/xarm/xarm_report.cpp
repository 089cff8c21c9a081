// SPDX-License-Identifier: MIT
#include "robot/arm/xarm/xarm_report.h"

#include <cmath>

#include "robot/arm/xarm/xarm_protocol.h"

namespace telesphere::xarm {

std::vector<std::uint8_t> encodeRealtimeReport(const RealtimeReport& report) {
  std::vector<std::uint8_t> out;
  out.reserve(kRealtimeReportBytes);
  appendU32(out, static_cast<std::uint32_t>(kRealtimeReportBytes));
  out.push_back(static_cast<std::uint8_t>((report.state & 0x0f) | (report.mode << 4)));
  appendU16(out, report.commands);
  for (double v : report.q) appendF32(out, static_cast<float>(v));
  for (double v : report.tool) appendF32(out, static_cast<float>(v));
  for (double v : report.torque) appendF32(out, static_cast<float>(v));
  return out;
}

std::vector<std::uint8_t> encodeNormalReport(const NormalReport& report) {
  std::vector<std::uint8_t> out = encodeRealtimeReport(report.realtime);
  out[0] = 0, out[1] = 0, out[2] = 0, out[3] = std::uint8_t(kNormalReportBytes);
  out.push_back(report.brakes);
  out.push_back(report.enabled);
  out.push_back(report.error);
  out.push_back(report.warning);
  for (double v : report.tcp_offset) appendF32(out, static_cast<float>(v));
  appendF32(out, static_cast<float>(report.payload_kg));
  for (double v : report.payload_com_mm) appendF32(out, static_cast<float>(v));
  out.push_back(report.collision_sensitivity);
  out.push_back(report.teach_sensitivity);
  for (double v : report.gravity) appendF32(out, static_cast<float>(v));
  return out;
}

void NormalReportReader::feed(std::span<const std::uint8_t> bytes) {
  if (failed()) return;
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
}

std::optional<NormalReport> NormalReportReader::next() {
  if (failed() || buffer_.size() < 4) return std::nullopt;
  const std::uint32_t field = readU32(buffer_, 0);
  if (field != kNormalReportBytes && field != kNormalReportLegacyLength) {
    error_ = "report length " + std::to_string(field) + " (a normal report has 145 bytes: is this port 30001?)";
    return std::nullopt;
  }
  if (length_field_ == 0) length_field_ = field;
  if (field != length_field_) {
    error_ = "report length changed from " + std::to_string(length_field_) + " to " + std::to_string(field);
    return std::nullopt;
  }
  if (buffer_.size() < kNormalReportBytes) return std::nullopt;
  const std::span<const std::uint8_t> in(buffer_.data(), kNormalReportBytes);
  NormalReport r;
  r.realtime.state = in[4] & 0x0f;
  r.realtime.mode = in[4] >> 4;
  r.realtime.commands = readU16(in, 5);
  for (std::size_t i = 0; i < 7; ++i) r.realtime.q[i] = readF32(in, 7 + 4 * i);
  for (std::size_t i = 0; i < 6; ++i) r.realtime.tool[i] = readF32(in, 35 + 4 * i);
  for (std::size_t i = 0; i < 7; ++i) r.realtime.torque[i] = readF32(in, 59 + 4 * i);
  r.brakes = in[87];
  r.enabled = in[88];
  r.error = in[89];
  r.warning = in[90];
  for (std::size_t i = 0; i < 6; ++i) r.tcp_offset[i] = readF32(in, 91 + 4 * i);
  r.payload_kg = readF32(in, 115);
  for (std::size_t i = 0; i < 3; ++i) r.payload_com_mm[i] = readF32(in, 119 + 4 * i);
  r.collision_sensitivity = in[131];
  r.teach_sensitivity = in[132];
  for (std::size_t i = 0; i < 3; ++i) r.gravity[i] = readF32(in, 133 + 4 * i);
  buffer_.erase(buffer_.begin(), buffer_.begin() + std::ptrdiff_t(kNormalReportBytes));
  if (r.realtime.state > 9 || r.realtime.mode > 11 || r.collision_sensitivity > 5 || r.teach_sensitivity > 5) {
    error_ = "normal report with state " + std::to_string(r.realtime.state) + ", mode " +
             std::to_string(r.realtime.mode) + ", sensitivities " + std::to_string(r.collision_sensitivity) + "/" +
             std::to_string(r.teach_sensitivity) + " (no such values: not port 30001?)";
    return std::nullopt;
  }
  return r;
}

void ReportReader::feed(std::span<const std::uint8_t> bytes) {
  if (failed()) return;
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
}

std::optional<RealtimeReport> ReportReader::next() {
  if (failed() || buffer_.size() < 4) return std::nullopt;
  const std::uint32_t length = readU32(buffer_, 0);
  if (length != kRealtimeReportBytes && length != kRealtimeReportWithForceBytes) {
    error_ = "report length " + std::to_string(length) + " (a real-time report has 87 or 135 bytes: is this port 30003?)";
    return std::nullopt;
  }
  if (length_ == 0) length_ = length;
  if (length != length_) {
    error_ = "report length changed from " + std::to_string(length_) + " to " + std::to_string(length);
    return std::nullopt;
  }
  if (buffer_.size() < length) return std::nullopt;
  const std::span<const std::uint8_t> in(buffer_.data(), length);
  RealtimeReport r;
  r.state = in[4] & 0x0f;
  r.mode = in[4] >> 4;
  r.commands = readU16(in, 5);
  for (std::size_t i = 0; i < 7; ++i) r.q[i] = readF32(in, 7 + 4 * i);
  for (std::size_t i = 0; i < 6; ++i) r.tool[i] = readF32(in, 35 + 4 * i);
  for (std::size_t i = 0; i < 7; ++i) r.torque[i] = readF32(in, 59 + 4 * i);
  buffer_.erase(buffer_.begin(), buffer_.begin() + length);
  if (r.state > 6 || r.mode > 11) {
    error_ = "report with state " + std::to_string(r.state) + ", mode " + std::to_string(r.mode) +
             " (no such values: not a real-time report stream?)";
    return std::nullopt;
  }
  for (double v : r.q)
    if (!std::isfinite(v)) {
      error_ = "report with a joint angle that is not a number";
      return std::nullopt;
    }
  return r;
}

}  // namespace telesphere::xarm
