// SPDX-License-Identifier: MIT
/// @brief Schema rules: any byte string parses to a valid envelope or a counted reason; version
///        and size limits hold before anything is allocated for an image.
#include <gtest/gtest.h>

#include <random>

#include "robot/link/link_schema.h"

namespace telesphere::link {
namespace {

std::string bytesOf(const proto::Envelope& e) { return e.SerializeAsString(); }

proto::StereoFrame frameOf(std::uint32_t w, std::uint32_t h, std::uint32_t left, std::uint32_t right) {
  proto::StereoFrame f;
  for (auto* image : {f.mutable_left(), f.mutable_right()}) {
    image->set_width(w);
    image->set_height(h);
  }
  f.mutable_left()->set_jpeg_bytes(left);
  f.mutable_right()->set_jpeg_bytes(right);
  return f;
}

TEST(LinkSchema, RandomBytesNeverCrashAndAreMostlyGarbage) {
  std::mt19937 rng(3);
  int accepted = 0;
  for (int i = 0; i < 20000; ++i) {
    std::string bytes(rng() % 64, '\0');
    for (auto& c : bytes) c = static_cast<char>(rng());
    DropReason why = DropReason::kCount;
    if (parseEnvelope(bytes.data(), bytes.size(), &why)) {
      ++accepted;  // only possible when the bytes happen to spell version 1 and a body
    } else {
      EXPECT_TRUE(why == DropReason::kGarbage || why == DropReason::kWrongSchemaVersion);
    }
  }
  EXPECT_LT(accepted, 20);
}

TEST(LinkSchema, VersionAndBodyAreRequired) {
  proto::Envelope e;
  e.set_schema_version(kSchemaVersion);
  DropReason why{};
  const std::string empty = bytesOf(e);
  EXPECT_FALSE(parseEnvelope(empty.data(), empty.size(), &why));
  EXPECT_EQ(why, DropReason::kGarbage);
  e.mutable_ping()->set_client_send_ns(5);
  const std::string good = bytesOf(e);
  ASSERT_TRUE(parseEnvelope(good.data(), good.size(), &why));
  e.set_schema_version(kSchemaVersion + 1);
  const std::string future = bytesOf(e);
  EXPECT_FALSE(parseEnvelope(future.data(), future.size(), &why));
  EXPECT_EQ(why, DropReason::kWrongSchemaVersion);
  const std::string huge(kMaxEnvelopeBytes + 1, 'x');
  EXPECT_FALSE(parseEnvelope(huge.data(), huge.size(), &why));
  EXPECT_EQ(why, DropReason::kOversized);
  // A control reply may carry a full-resolution stereo still (two 4K grey images).
  proto::Envelope reply;
  reply.set_schema_version(kSchemaVersion);
  reply.mutable_control_reply()->mutable_still()->mutable_left()->set_gray8(std::string(3840 * 2160, '\x80'));
  reply.mutable_control_reply()->mutable_still()->mutable_right()->set_gray8(std::string(3840 * 2160, '\x40'));
  const std::string still = bytesOf(reply);
  EXPECT_FALSE(parseEnvelope(still.data(), still.size(), &why));
  EXPECT_EQ(why, DropReason::kOversized);
  const auto parsed = parseEnvelope(still.data(), still.size(), &why, nullptr, kMaxControlReplyBytes);
  ASSERT_TRUE(parsed);
  EXPECT_EQ(parsed->control_reply().still().right().gray8().size(), 3840u * 2160u);
}

TEST(LinkSchema, StereoFrameLimits) {
  EXPECT_FALSE(checkStereoFrame(frameOf(3840, 2160, 100, 200), 100, 200));
  EXPECT_EQ(checkStereoFrame(frameOf(100000, 100000, 100, 200), 100, 200), DropReason::kBadImageSize);
  EXPECT_EQ(checkStereoFrame(frameOf(0, 2160, 100, 200), 100, 200), DropReason::kBadImageSize);
  EXPECT_EQ(checkStereoFrame(frameOf(3840, 2160, 100, 200), 100, 201), DropReason::kBadImageSize);
  EXPECT_EQ(checkStereoFrame(frameOf(3840, 2160, 100, 0), 100, 0), DropReason::kBadImageSize);
  EXPECT_EQ(checkStereoFrame(frameOf(3840, 2160, 0, 0), kMaxJpegBytes + 1, 5), DropReason::kOversized);
  proto::StereoFrame one_eye = frameOf(3840, 2160, 100, 200);
  one_eye.clear_right();
  EXPECT_EQ(checkStereoFrame(one_eye, 100, 200), DropReason::kBadImageSize);
}

}  // namespace
}  // namespace telesphere::link
