// SPDX-License-Identifier: MIT
#include "robot/xarm/xarm_report.h"

#include <cmath>

#include "robot/xarm/xarm_protocol.h"

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
