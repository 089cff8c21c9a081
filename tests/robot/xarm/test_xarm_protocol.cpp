// SPDX-License-Identifier: MIT
/// @brief The xArm protocol codec (robot/xarm/): the manual's example bytes, frames and reports
///        reassembled from any split of the byte stream, malformed and truncated input refused with
///        a reason, parameter byte orders, and the code tables.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "robot/xarm/xarm_codes.h"
#include "robot/xarm/xarm_protocol.h"
#include "robot/xarm/xarm_report.h"

namespace telesphere::xarm {
namespace {

using Bytes = std::vector<std::uint8_t>;

TEST(XArmFrame, EncodesTheManualsEnableAllJointsExample) {
  // Developer manual, register 11: "00 01 00 02 00 03 0B 08 01".
  EXPECT_EQ(encodeRequest(1, Register::kMotionEnable, Bytes{8, 1}), (Bytes{0x00, 0x01, 0x00, 0x02, 0x00, 0x03, 0x0B, 0x08, 0x01}));
  // ... and its reply "00 01 00 02 00 02 0B 10": status 0x10 (not ready), no parameters.
  EXPECT_EQ(encodeResponse(1, 0x0B, 0x10, {}), (Bytes{0x00, 0x01, 0x00, 0x02, 0x00, 0x02, 0x0B, 0x10}));
}

TEST(XArmFrame, ReassemblesFramesFromEverySplitOfTheStream) {
  Bytes stream = encodeResponse(7, 13, 0x20, Bytes{2});
  const Bytes second = encodeResponse(8, 15, 0x40, Bytes{31, 0});
  stream.insert(stream.end(), second.begin(), second.end());
  for (std::size_t cut = 0; cut <= stream.size(); ++cut) {
    FrameReader reader;
    reader.feed(std::span(stream).first(cut));
    std::vector<Frame> frames;
    while (auto f = reader.next()) frames.push_back(*f);
    reader.feed(std::span(stream).subspan(cut));
    while (auto f = reader.next()) frames.push_back(*f);
    ASSERT_FALSE(reader.failed()) << cut;
    ASSERT_EQ(frames.size(), 2u) << cut;
    EXPECT_EQ(frames[0].transaction, 7);
    EXPECT_EQ(frames[0].reg, 13);
    EXPECT_EQ(frames[0].status(), 0x20);
    EXPECT_EQ(frames[0].replyParams().size(), 1u);
    EXPECT_EQ(frames[1].status() & kStatusError, kStatusError);
    EXPECT_EQ(frames[1].replyParams()[0], 31);
    EXPECT_EQ(reader.buffered(), 0u);
  }
}

TEST(XArmFrame, RefusesForeignProtocolsAndImpossibleLengthsForGood) {
  for (const Bytes& bad : {Bytes{0, 1, 0, 7, 0, 2, 13, 0},            // protocol id 7
                           Bytes{0, 1, 0, 2, 0, 0, 13},               // length 0
                           Bytes{0, 1, 0, 2, 0xff, 0xff, 13, 0}}) {   // length beyond the maximum
    FrameReader reader;
    reader.feed(bad);
    EXPECT_FALSE(reader.next());
    EXPECT_TRUE(reader.failed());
    EXPECT_FALSE(reader.error().empty());
    reader.feed(encodeResponse(1, 13, 0, Bytes{2}));  // no resynchronisation afterwards
    EXPECT_FALSE(reader.next());
  }
  FrameReader truncated;  // a frame that never completes is just waited for
  const Bytes servo = encodeRequest(3, Register::kMoveServoJoint, servoJointParams({}));
  truncated.feed(std::span(servo).first(20));
  EXPECT_FALSE(truncated.next());
  EXPECT_FALSE(truncated.failed());
}

TEST(XArmParams, FloatsAreLittleEndianAndShortsBigEndianAsTheProtocolFixes) {
  Bytes out;
  appendF32(out, 1.0f);  // 0x3F800000
  EXPECT_EQ(out, (Bytes{0x00, 0x00, 0x80, 0x3F}));
  out.clear();
  appendU16(out, 0x1234);
  appendU32(out, 87);
  EXPECT_EQ(out, (Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x57}));
  EXPECT_EQ(readU16(out, 0), 0x1234);
  EXPECT_EQ(readU32(out, 2), 87u);
}

TEST(XArmParams, ServoAndMoveJointParametersRoundTripWithJ7AndTheIgnoredValuesZero) {
  const std::array<double, 6> q{0.1, -1.2, -0.7, 3.0, -1.5, 6.2};
  const Bytes servo = servoJointParams(q);
  ASSERT_EQ(servo.size(), 40u);  // 10 × FP32, length field 0x29 with the register
  EXPECT_EQ(encodeRequest(1, Register::kMoveServoJoint, servo)[5], 0x29);
  for (std::size_t i = 6; i < 10; ++i) EXPECT_EQ(readF32(servo, 4 * i), 0.0f) << i;
  const auto back = jointsOfMoveParams(servo);
  ASSERT_TRUE(back);
  for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR((*back)[i], q[i], 1e-6);
  const Bytes move = moveJointParams(q, 0.35, 1.0);
  EXPECT_NEAR(readF32(move, 28), 0.35, 1e-7);
  EXPECT_NEAR(readF32(move, 32), 1.0, 1e-7);
  EXPECT_FALSE(jointsOfMoveParams(std::span(servo).first(39)));
}

RealtimeReport sampleReport() {
  RealtimeReport r;
  r.state = 1;
  r.mode = 1;
  r.commands = 3;
  r.q = {0.25, -0.5, -1.0, 0.125, -0.75, 3.0, 0.0};
  r.tool = {300, 0, 200, 3.14, 0, 0};
  r.torque = {1, 2, 3, 4, 5, 6, 0};
  return r;
}

TEST(XArmReport, RoundTripsThe87ByteReportFromEverySplit) {
  const Bytes one = encodeRealtimeReport(sampleReport());
  ASSERT_EQ(one.size(), kRealtimeReportBytes);
  EXPECT_EQ(one[4], 0x11);  // state in the low nibble, mode in the high one
  Bytes stream = one;
  stream.insert(stream.end(), one.begin(), one.end());
  for (std::size_t cut = 0; cut <= stream.size(); cut += 5) {
    ReportReader reader;
    int got = 0;
    reader.feed(std::span(stream).first(cut));
    while (auto r = reader.next()) ++got;
    reader.feed(std::span(stream).subspan(cut));
    while (auto r = reader.next()) {
      ++got;
      EXPECT_EQ(r->state, 1);
      EXPECT_EQ(r->mode, 1);
      EXPECT_EQ(r->commands, 3);
      for (std::size_t i = 0; i < 7; ++i) EXPECT_EQ(r->q[i], sampleReport().q[i]);  // exact in float
      EXPECT_NEAR(r->tool[3], 3.14, 1e-6);
    }
    EXPECT_EQ(got, 2) << cut;
    EXPECT_FALSE(reader.failed());
  }
}

TEST(XArmReport, AcceptsTheForceTorqueLengthAndRefusesOthersChangesAndNonsense) {
  Bytes with_force = encodeRealtimeReport(sampleReport());
  with_force.resize(kRealtimeReportWithForceBytes, 0);
  with_force[3] = std::uint8_t(kRealtimeReportWithForceBytes);
  ReportReader force;
  force.feed(with_force);
  EXPECT_TRUE(force.next());
  // Then an 87-byte one: the length changed mid-stream.
  force.feed(encodeRealtimeReport(sampleReport()));
  EXPECT_FALSE(force.next());
  EXPECT_TRUE(force.failed());

  Bytes normal_port = encodeRealtimeReport(sampleReport());  // a 145-byte "normal" report: wrong port
  normal_port[3] = 145;
  ReportReader wrong;
  wrong.feed(normal_port);
  EXPECT_FALSE(wrong.next());
  EXPECT_NE(wrong.error().find("30003"), std::string::npos) << wrong.error();

  RealtimeReport bad_state = sampleReport();
  bad_state.state = 9;
  ReportReader state;
  state.feed(encodeRealtimeReport(bad_state));
  EXPECT_FALSE(state.next());
  EXPECT_TRUE(state.failed());

  RealtimeReport nan = sampleReport();
  nan.q[2] = std::numeric_limits<double>::quiet_NaN();
  ReportReader joint;
  joint.feed(encodeRealtimeReport(nan));
  EXPECT_FALSE(joint.next());
  EXPECT_TRUE(joint.failed());
}

TEST(XArmReport, RandomBytesNeverCrashAndNeverYieldANonFiniteJoint) {
  std::mt19937 rng(17);
  for (int trial = 0; trial < 2000; ++trial) {
    Bytes junk(std::size_t(rng() % 300));
    for (auto& b : junk) b = std::uint8_t(rng());
    if (trial % 2 == 0 && junk.size() >= 4) {  // half of them with a plausible length
      junk[0] = junk[1] = junk[2] = 0;
      junk[3] = 87;
    }
    ReportReader reports;
    reports.feed(junk);
    while (auto r = reports.next())
      for (double v : r->q) EXPECT_TRUE(std::isfinite(v));
    FrameReader frames;
    frames.feed(junk);
    while (auto f = frames.next()) EXPECT_LE(f->body.size() + 7, kMaxFrameBytes);
  }
}

TEST(XArmCodes, ErrorsAndWarningsReadAsTheManualsText) {
  EXPECT_EQ(controllerErrorText(22), "C22 self-collision error");
  EXPECT_EQ(controllerErrorText(31), "C31 collision caused abnormal current");
  EXPECT_EQ(controllerErrorText(0), "no error");
  EXPECT_NE(controllerErrorText(99).find("unknown"), std::string::npos);
  EXPECT_EQ(controllerWarningText(11), "warning 11: the controller's command cache is full");
  EXPECT_TRUE(isEmergencyStop(1));
  EXPECT_TRUE(isEmergencyStop(3));
  EXPECT_FALSE(isEmergencyStop(31));
  EXPECT_EQ(stateName(4), "stopped");
  EXPECT_EQ(modeName(1), "servo");
}

}  // namespace
}  // namespace telesphere::xarm
