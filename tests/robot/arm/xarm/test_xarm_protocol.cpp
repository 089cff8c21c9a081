// SPDX-License-Identifier: MIT
/// @brief The xArm protocol codec (robot/arm/xarm/): the manual's example bytes, frames and reports
///        reassembled from any split of the byte stream, malformed and truncated input refused with
///        a reason, parameter byte orders, and the code tables.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "robot/arm/xarm/xarm_codes.h"
#include "robot/arm/xarm/xarm_protocol.h"
#include "robot/arm/xarm/xarm_report.h"

namespace telesphere::xarm {
namespace {

using Bytes = std::vector<std::uint8_t>;

TEST(XArmFrame, EncodesTheManualsEnableAllJointsExample) {
  // Developer manual, register 11: "00 01 00 02 00 03 0B 08 01".
  EXPECT_EQ(encodeRequest(1, Register::kMotionEnable, Bytes{8, 1}), (Bytes{0x00, 0x01, 0x00, 0x02, 0x00, 0x03, 0x0B, 0x08, 0x01}));
  // ... and its reply "00 01 00 02 00 02 0B 10": status 0x10 (not ready), no parameters.
  EXPECT_EQ(encodeResponse(1, 0x0B, 0x10, {}), (Bytes{0x00, 0x01, 0x00, 0x02, 0x00, 0x02, 0x0B, 0x10}));
}

// Byte sequences written from UFACTORY's developer documentation and its clients' sources (read,
// not copied; robot/arm/xarm/README.md names them), not from our own encoder.
TEST(XArmFrame, TheVendorsExamplesForPayloadSensitivityStateAndErrorCodes) {
  // Register 36, 1 kg at (400, 0, 200) mm, transaction 1 (the documentation's own example) …
  EXPECT_EQ(encodeRequest(1, Register::kSetTcpLoad, tcpLoadParams(1.0, {400.0, 0.0, 200.0})),
            (Bytes{0x00, 0x01, 0x00, 0x02, 0x00, 0x11, 0x24, 0x00, 0x00, 0x80, 0x3F, 0x00, 0x00, 0xC8, 0x43, 0x00, 0x00,
                   0x00, 0x00, 0x00, 0x00, 0x48, 0x43}));
  // … and its reply, status 0x20 (a warning), no parameters.
  FrameReader reader;
  reader.feed(Bytes{0x00, 0x01, 0x00, 0x02, 0x00, 0x02, 0x24, 0x20});
  auto reply = reader.next();
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->reg, 0x24);
  EXPECT_EQ(reply->status(), kStatusWarning);
  EXPECT_TRUE(reply->replyParams().empty());
  // Register 37, sensitivity 3.
  EXPECT_EQ(encodeRequest(10, Register::kSetCollisionSensitivity, Bytes{3}),
            (Bytes{0x00, 0x0A, 0x00, 0x02, 0x00, 0x02, 0x25, 0x03}));
  // Get state with identifier 3 (firmware ≥ 1.8.6), and the controller's reply echoing it: state 2.
  EXPECT_EQ(encodeRequest(7, Register::kGetState, {}, kPrivateProtocolWithHeartbeat),
            (Bytes{0x00, 0x07, 0x00, 0x03, 0x00, 0x01, 0x0D}));
  EXPECT_EQ(encodeResponse(7, 0x0D, 0x00, Bytes{2}, kPrivateProtocolWithHeartbeat),
            (Bytes{0x00, 0x07, 0x00, 0x03, 0x00, 0x03, 0x0D, 0x00, 0x02}));
  // Error and warning codes: status bit 6 (error), C31, no warning.
  reader.feed(Bytes{0x00, 0x0B, 0x00, 0x02, 0x00, 0x04, 0x0F, 0x40, 0x1F, 0x00});
  reply = reader.next();
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->status(), kStatusError);
  ASSERT_EQ(reply->replyParams().size(), 2u);
  EXPECT_EQ(reply->replyParams()[0], 31);
  // The old heartbeat frame some clients send every second: identifier 1, taken as a frame.
  reader.feed(Bytes{0x00, 0x00, 0x00, 0x01, 0x00, 0x02, 0x00, 0x00});
  reply = reader.next();
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->protocol, kHeartbeatProtocol);
  EXPECT_FALSE(reader.failed());
}

TEST(XArmFirmware, VersionSerialAndIdentifierAsTheVendorsClientsReadThem) {
  const auto reply = [](const std::string& text) {
    Bytes b(40, 0);
    std::copy(text.begin(), text.end(), b.begin());
    return b;
  };
  // The documentation's example of register 1.
  auto v = parseFirmwareVersion(reply("6,6,XI1202,AC1302,v1.12.10"));
  ASSERT_TRUE(v);
  EXPECT_EQ(v->axis, 6);
  EXPECT_EQ(v->type, 6);
  EXPECT_EQ(v->arm_sn, "XI1202");
  EXPECT_EQ(v->box_sn, "AC1302");
  EXPECT_EQ(v->major, 1);
  EXPECT_EQ(v->minor, 12);
  EXPECT_EQ(v->patch, 10);
  EXPECT_EQ(v->protocol(), kPrivateProtocolWithHeartbeat);
  // The switch to identifier 3 comes with 1.8.6, not before.
  EXPECT_EQ(parseFirmwareVersion(reply("6,6,XI1202,AC1302,v1.8.5"))->protocol(), kPrivateProtocol);
  EXPECT_EQ(parseFirmwareVersion(reply("6,6,XI1202,AC1302,v1.8.6"))->protocol(), kPrivateProtocolWithHeartbeat);
  EXPECT_EQ(parseFirmwareVersion(reply("7,7,XS1304,AC1303,v2.5.5"))->axis, 7);
  // A bare version (old firmware) and nonsense.
  EXPECT_EQ(parseFirmwareVersion(reply("v1.2.3"))->minor, 2);
  EXPECT_FALSE(parseFirmwareVersion(reply("no version here")));
  EXPECT_FALSE(parseFirmwareVersion(Bytes{}));
  // Register 2: the arm's serial, NUL, the control box's (the documentation's example).
  Bytes sn(40, 0);
  const std::string text = std::string("XI120204201B02") + '\0' + "AC130202B02L02\n";
  std::copy(text.begin(), text.end(), sn.begin());
  EXPECT_EQ(armSerialOfReply(sn), "XI120204201B02");
  // Characters 2–5 are the digits the vendor's joint-range check reads.
  EXPECT_EQ(std::stoi(armSerialOfReply(sn).substr(2, 4)), 1202);
}

TEST(XArmReport, TheNormalReportsPayloadAndSensitivitiesAtTheDocumentedOffsets) {
  // 145 bytes built by hand at the documented offsets (not by our encoder).
  Bytes frame(145, 0);
  frame[3] = 145;
  frame[4] = 0x12;  // mode 1 (servo), state 2 (ready)
  const auto put = [&](std::size_t at, float v) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, 4);
    for (int i = 0; i < 4; ++i) frame[at + std::size_t(i)] = std::uint8_t(bits >> (8 * i));
  };
  put(7, 0.25f);  // J1
  frame[89] = 31;  // error code
  put(115, 1.2f);
  put(119, 0.0f);
  put(123, -5.0f);
  put(127, 60.0f);
  frame[131] = 2;
  frame[132] = 3;
  for (std::size_t cut : {std::size_t(0), std::size_t(3), std::size_t(100), std::size_t(145)}) {
    NormalReportReader reader;
    reader.feed(std::span(frame).first(cut));
    auto r = reader.next();
    if (cut < 145) {
      EXPECT_FALSE(r);
      reader.feed(std::span(frame).subspan(cut));
      r = reader.next();
    }
    ASSERT_TRUE(r) << reader.error();
    EXPECT_EQ(r->realtime.state, 2);
    EXPECT_EQ(r->realtime.mode, 1);
    EXPECT_FLOAT_EQ(float(r->realtime.q[0]), 0.25f);
    EXPECT_EQ(r->error, 31);
    EXPECT_FLOAT_EQ(float(r->payload_kg), 1.2f);
    EXPECT_FLOAT_EQ(float(r->payload_com_mm[1]), -5.0f);
    EXPECT_FLOAT_EQ(float(r->payload_com_mm[2]), 60.0f);
    EXPECT_EQ(r->collision_sensitivity, 2);
    EXPECT_EQ(r->teach_sensitivity, 3);
  }
  // Our encoder writes the same bytes where they matter; the legacy length field 133 is taken.
  NormalReport report;
  report.realtime.state = 2;
  report.realtime.mode = 1;
  report.realtime.q[0] = 0.25;
  report.error = 31;
  report.payload_kg = 1.2;
  report.payload_com_mm = {0.0, -5.0, 60.0};
  report.collision_sensitivity = 2;
  report.teach_sensitivity = 3;
  Bytes encoded = encodeNormalReport(report);
  ASSERT_EQ(encoded.size(), 145u);
  for (std::size_t i : {std::size_t(3), std::size_t(4), std::size_t(89), std::size_t(115), std::size_t(118), std::size_t(131)})
    EXPECT_EQ(encoded[i], frame[i]) << i;
  encoded[3] = 133;
  NormalReportReader legacy;
  legacy.feed(encoded);
  EXPECT_TRUE(legacy.next());
  // A sensitivity of 9 or another length: not a normal report stream.
  frame[131] = 9;
  NormalReportReader bad;
  bad.feed(frame);
  EXPECT_FALSE(bad.next());
  EXPECT_TRUE(bad.failed());
  NormalReportReader wrong_port;
  wrong_port.feed(encodeRealtimeReport({}));
  EXPECT_FALSE(wrong_port.next());
  EXPECT_NE(wrong_port.error().find("port 30001"), std::string::npos) << wrong_port.error();
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
