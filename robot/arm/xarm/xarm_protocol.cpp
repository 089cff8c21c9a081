// SPDX-License-Identifier: MIT
#include "robot/arm/xarm/xarm_protocol.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace telesphere::xarm {

std::vector<std::uint8_t> encodeRequest(std::uint16_t transaction, Register reg, std::span<const std::uint8_t> params,
                                        std::uint16_t protocol) {
  std::vector<std::uint8_t> out;
  out.reserve(7 + params.size());
  appendU16(out, transaction);
  appendU16(out, protocol);
  appendU16(out, static_cast<std::uint16_t>(1 + params.size()));
  out.push_back(static_cast<std::uint8_t>(reg));
  out.insert(out.end(), params.begin(), params.end());
  return out;
}

std::vector<std::uint8_t> encodeResponse(std::uint16_t transaction, std::uint8_t reg, std::uint8_t status,
                                         std::span<const std::uint8_t> params, std::uint16_t protocol) {
  std::vector<std::uint8_t> out;
  out.reserve(8 + params.size());
  appendU16(out, transaction);
  appendU16(out, protocol);
  appendU16(out, static_cast<std::uint16_t>(2 + params.size()));
  out.push_back(reg);
  out.push_back(status);
  out.insert(out.end(), params.begin(), params.end());
  return out;
}

void FrameReader::feed(std::span<const std::uint8_t> bytes) {
  if (failed()) return;
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
}

std::optional<Frame> FrameReader::next() {
  if (failed() || buffer_.size() < 6) return std::nullopt;
  const std::uint16_t protocol = readU16(buffer_, 2);
  const std::uint16_t length = readU16(buffer_, 4);
  if (protocol > kPrivateProtocolWithHeartbeat) {
    error_ = "protocol id " + std::to_string(protocol) + " (not an xArm frame)";
    return std::nullopt;
  }
  if (length == 0 || 6u + length > kMaxFrameBytes) {
    error_ = "frame length " + std::to_string(length) + " outside 1.." + std::to_string(kMaxFrameBytes - 6);
    return std::nullopt;
  }
  if (buffer_.size() < 6u + length) return std::nullopt;
  Frame frame;
  frame.transaction = readU16(buffer_, 0);
  frame.protocol = protocol;
  frame.reg = buffer_[6];
  frame.body.assign(buffer_.begin() + 7, buffer_.begin() + 6 + length);
  buffer_.erase(buffer_.begin(), buffer_.begin() + 6 + length);
  return frame;
}

void appendF32(std::vector<std::uint8_t>& out, float value) {
  const auto bits = std::bit_cast<std::uint32_t>(value);
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(bits >> (8 * i)));
}

float readF32(std::span<const std::uint8_t> in, std::size_t offset) {
  std::uint32_t bits = 0;
  for (int i = 0; i < 4; ++i) bits |= std::uint32_t(in[offset + std::size_t(i)]) << (8 * i);
  return std::bit_cast<float>(bits);
}

void appendU16(std::vector<std::uint8_t>& out, std::uint16_t value) {
  out.push_back(static_cast<std::uint8_t>(value >> 8));
  out.push_back(static_cast<std::uint8_t>(value));
}

std::uint16_t readU16(std::span<const std::uint8_t> in, std::size_t offset) {
  return static_cast<std::uint16_t>((in[offset] << 8) | in[offset + 1]);
}

void appendU32(std::vector<std::uint8_t>& out, std::uint32_t value) {
  for (int i = 3; i >= 0; --i) out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
}

std::uint32_t readU32(std::span<const std::uint8_t> in, std::size_t offset) {
  return (std::uint32_t(in[offset]) << 24) | (std::uint32_t(in[offset + 1]) << 16) |
         (std::uint32_t(in[offset + 2]) << 8) | std::uint32_t(in[offset + 3]);
}

namespace {

std::vector<std::uint8_t> jointParams(const std::array<double, 6>& q, double a, double b) {
  std::vector<std::uint8_t> out;
  out.reserve(40);
  for (double v : q) appendF32(out, static_cast<float>(v));
  appendF32(out, 0.0f);  // J7: none on an xArm 6
  appendF32(out, static_cast<float>(a));
  appendF32(out, static_cast<float>(b));
  appendF32(out, 0.0f);  // mvtime
  return out;
}

}  // namespace

bool FirmwareVersion::atLeast(int ma, int mi, int pa) const {
  if (major != ma) return major > ma;
  if (minor != mi) return minor > mi;
  return patch >= pa;
}

std::optional<FirmwareVersion> parseFirmwareVersion(std::span<const std::uint8_t> reply) {
  const std::string text(reply.begin(), std::find(reply.begin(), reply.end(), std::uint8_t(0)));
  FirmwareVersion v;
  // "axis,type,armSN,boxSN,vX.Y.Z": the fields before the version when there are four commas.
  std::vector<std::string> fields;
  std::size_t start = 0;
  for (std::size_t comma; (comma = text.find(',', start)) != std::string::npos; start = comma + 1)
    fields.push_back(text.substr(start, comma - start));
  fields.push_back(text.substr(start));
  if (fields.size() >= 5) {
    v.axis = std::atoi(fields[0].c_str());
    v.type = std::atoi(fields[1].c_str());
    v.arm_sn = fields[2];
    v.box_sn = fields[3];
  }
  // The version: the last "v" (or "V") followed by a digit.
  std::size_t at = std::string::npos;
  for (std::size_t i = 0; i + 1 < text.size(); ++i)
    if ((text[i] == 'v' || text[i] == 'V') && std::isdigit(static_cast<unsigned char>(text[i + 1]))) at = i;
  if (at == std::string::npos || std::sscanf(text.c_str() + at + 1, "%d.%d.%d", &v.major, &v.minor, &v.patch) != 3)
    return std::nullopt;
  return v;
}

std::string armSerialOfReply(std::span<const std::uint8_t> reply) {
  return std::string(reply.begin(), std::find(reply.begin(), reply.end(), std::uint8_t(0)));
}

std::vector<std::uint8_t> tcpLoadParams(double mass_kg, const std::array<double, 3>& com_mm) {
  std::vector<std::uint8_t> out;
  appendF32(out, static_cast<float>(mass_kg));
  for (double v : com_mm) appendF32(out, static_cast<float>(v));
  return out;
}

std::vector<std::uint8_t> servoJointParams(const std::array<double, 6>& q) { return jointParams(q, 0.0, 0.0); }

std::vector<std::uint8_t> moveJointParams(const std::array<double, 6>& q, double speed, double acceleration) {
  return jointParams(q, speed, acceleration);
}

std::optional<std::array<double, 6>> jointsOfMoveParams(std::span<const std::uint8_t> params) {
  if (params.size() < 40) return std::nullopt;
  std::array<double, 6> q{};
  for (std::size_t i = 0; i < 6; ++i) q[i] = readF32(params, 4 * i);
  return q;
}

std::string registerName(std::uint8_t reg) {
  switch (static_cast<Register>(reg)) {
    case Register::kGetVersion: return "get version (1)";
    case Register::kGetRobotSn: return "get serial number (2)";
    case Register::kSetTcpLoad: return "set payload (36)";
    case Register::kSetCollisionSensitivity: return "set collision sensitivity (37)";
    case Register::kMotionEnable: return "motion enable (11)";
    case Register::kSetState: return "set state (12)";
    case Register::kGetState: return "get state (13)";
    case Register::kGetCmdNum: return "get command count (14)";
    case Register::kGetErrorWarning: return "get error/warning (15)";
    case Register::kCleanError: return "clean error (16)";
    case Register::kCleanWarning: return "clean warning (17)";
    case Register::kSetMode: return "set mode (19)";
    case Register::kMoveJoint: return "move joint (23)";
    case Register::kMoveServoJoint: return "servo joint (29)";
    case Register::kGetJointPositions: return "get joint positions (42)";
  }
  return "register " + std::to_string(reg);
}

std::string stateName(std::uint8_t state) {
  switch (state) {
    case 0: return "start";
    case 1: return "moving";
    case 2: return "ready";
    case 3: return "paused";
    case 4: return "stopped";
    case 5: return "mode changed (needs set state 0)";
    case 6: return "decelerating to a stop";
  }
  return "state " + std::to_string(state);
}

std::string modeName(std::uint8_t mode) {
  switch (mode) {
    case 0: return "position";
    case 1: return "servo";
    case 2: return "joint teaching";
    case 3: return "cartesian teaching";
    case 4: return "joint velocity";
    case 5: return "cartesian velocity";
    case 6: return "joint online planning";
    case 7: return "cartesian online planning";
  }
  return "mode " + std::to_string(mode);
}

}  // namespace telesphere::xarm
