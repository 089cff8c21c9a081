// SPDX-License-Identifier: MIT
/// @brief FrameIdTracker: in-order ids, gaps counted as lost, GigE Vision 16-bit block-id wrap (with
///        and without id 0), counter restarts, and the unwrapped sequence.
#include <gtest/gtest.h>

#include "robot/cameras/frame_id_tracker.h"

namespace telesphere::robot {
namespace {

TEST(FrameIdTracker, CountsGapsAndKeepsTheSequence) {
  cameras::FrameIdTracker t;
  auto s = t.next(100);
  EXPECT_TRUE(s.resynced);
  EXPECT_EQ(s.sequence, 100u);
  s = t.next(101);
  EXPECT_EQ(s.lost, 0u);
  EXPECT_EQ(s.sequence, 101u);
  s = t.next(105);
  EXPECT_EQ(s.lost, 3u);
  EXPECT_EQ(s.sequence, 105u);
  EXPECT_FALSE(s.resynced);
}

TEST(FrameIdTracker, GigEVisionBlockIdsWrapSkippingZero) {
  cameras::FrameIdTracker t;
  t.next(65534);
  auto s = t.next(65535);
  EXPECT_EQ(s.lost, 0u);
  s = t.next(1);  // 0 is never used by GEV 1.x block ids
  EXPECT_EQ(s.lost, 0u);
  EXPECT_FALSE(s.resynced);
  EXPECT_EQ(s.sequence, 65536u);
  t.next(65534);  // 1 → 65534: far beyond max_gap, a restart, not a wrap
  s = t.next(65535);
  s = t.next(3);  // 1 and 2 lost across the wrap
  EXPECT_EQ(s.lost, 2u);
}

TEST(FrameIdTracker, WrapWithZeroUsedCountsZeroAsAFrame) {
  cameras::FrameIdTracker t;
  t.next(0);
  t.next(1);
  t.next(65535);  // big forward step: restart
  auto s = t.next(0);
  EXPECT_EQ(s.lost, 0u);
  s = t.next(2);
  EXPECT_EQ(s.lost, 1u);
}

TEST(FrameIdTracker, RestartsAndHugeJumpsResyncWithoutCountingLoss) {
  cameras::FrameIdTracker t(1000);
  t.next(500'000);
  auto s = t.next(500'001);
  const std::uint64_t seq = s.sequence;
  s = t.next(7);  // counter restarted (camera re-opened)
  EXPECT_TRUE(s.resynced);
  EXPECT_EQ(s.lost, 0u);
  EXPECT_EQ(s.sequence, seq + 1);
  s = t.next(9'000'000);  // far beyond max_gap: restart as well
  EXPECT_TRUE(s.resynced);
  EXPECT_EQ(s.lost, 0u);
  EXPECT_EQ(s.sequence, seq + 2);
  t.reset();
  s = t.next(12);
  EXPECT_TRUE(s.resynced);
  EXPECT_EQ(s.sequence, seq + 3);
  s = t.next(14);
  EXPECT_EQ(s.lost, 1u);
  EXPECT_EQ(s.sequence, seq + 5);
}

}  // namespace
}  // namespace telesphere::robot
