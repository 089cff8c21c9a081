// SPDX-License-Identifier: MIT
/// @brief TimeSeries: order, trimming, range queries, absolute indices and revisions, memory.
#include <gtest/gtest.h>

#include <cmath>

#include "console/telemetry/time_series.h"

namespace telesphere::console::telemetry {
namespace {

TEST(TimeSeries, KeepsTimeOrderAndTrims) {
  TimeSeries s;
  for (double t : {1.0, 2.0, 4.0, 3.0, 0.5, 4.0}) s.append(t, t * 10);
  s.append(std::nan(""), 1.0);  // ignored
  ASSERT_EQ(s.size(), 6u);
  for (std::size_t i = 1; i < s.size(); ++i) EXPECT_LE(s[i - 1].t, s[i].t);
  EXPECT_EQ(s.front().t, 0.5);
  s.trimBefore(2.0);
  EXPECT_EQ(s.size(), 4u);
  EXPECT_EQ(s.front().t, 2.0);
  s.keepNewest(1);
  EXPECT_EQ(s.size(), 1u);
  EXPECT_EQ(s.back().t, 4.0);
  const auto [a, b] = s.indexRange(0, 10);
  EXPECT_EQ(b - a, 1u);
}

TEST(TimeSeries, AbsoluteIndicesAndRevisions) {
  TimeSeries s;
  for (int i = 0; i < 10; ++i) s.append(i, i);
  const auto r0 = s.revision();
  s.trimBefore(3);
  EXPECT_EQ(s.removed(), 3u);
  EXPECT_EQ(s.front().t, 3.0);
  s.keepNewest(5);
  EXPECT_EQ(s.removed(), 5u);
  EXPECT_EQ(s.revision(), r0);  // trimming and appending keep the revision
  s.append(20, 0);
  EXPECT_EQ(s.revision(), r0);
  s.append(7.5, 0);  // out of order
  EXPECT_NE(s.revision(), r0);
  const auto r1 = s.revision();
  s.clear();
  EXPECT_NE(s.revision(), r1);
  EXPECT_EQ(s.removed(), 12u);
}

TEST(TimeSeries, MemoryFollowsTheSampleCount) {
  TimeSeries s;
  for (int i = 0; i < 100000; ++i) s.append(i * 0.001, i);
  const std::size_t full = s.bytes();
  EXPECT_GE(full, 100000 * sizeof(Sample));
  EXPECT_LE(full, 100000 * sizeof(Sample) * 2);
  s.trimBefore(90.0);
  EXPECT_LT(s.bytes(), full / 5);
}

}  // namespace
}  // namespace telesphere::console::telemetry
