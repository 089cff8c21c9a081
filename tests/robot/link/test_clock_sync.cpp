// SPDX-License-Identifier: MIT
/// @brief ClockSync on synthetic exchanges with a known offset and asymmetric queueing delays.
#include <gtest/gtest.h>

#include <random>

#include "robot/link/clock_sync.h"

namespace telesphere::link {
namespace {

TEST(ClockSync, RecoversTheOffsetWithinHalfTheBestRoundTrip) {
  const std::int64_t offset = 123'456'789'000;  // client clock runs this far ahead of the server
  std::mt19937 rng(11);
  std::exponential_distribution<double> queueing(1.0 / 2e6);  // mean 2 ms of extra delay per leg
  ClockSync sync;
  EXPECT_FALSE(sync.estimate());
  std::int64_t t_client = 1'000'000'000;
  for (int i = 0; i < 100; ++i) {
    const std::int64_t up = 100'000 + static_cast<std::int64_t>(queueing(rng));
    const std::int64_t down = 100'000 + static_cast<std::int64_t>(queueing(rng));
    const std::int64_t server = t_client + up - offset;
    sync.addSample(t_client, server, t_client + up + down);
    t_client += 200'000'000;
  }
  const auto e = sync.estimate();
  ASSERT_TRUE(e);
  EXPECT_LE(std::abs(e->server_to_client_offset_ns - offset), e->round_trip_ns / 2);
  EXPECT_LT(e->round_trip_ns, 1'000'000);  // the best of the last 32 exchanges
  EXPECT_EQ(*sync.serverToClient(0), e->server_to_client_offset_ns);
}

TEST(ClockSync, IgnoresImpossibleSamplesAndHugeClocks) {
  ClockSync sync;
  sync.addSample(100, 50, 90);  // received before sent
  EXPECT_FALSE(sync.estimate());
  const std::int64_t big = std::numeric_limits<std::int64_t>::max() - 10;
  sync.addSample(big - 4, 7, big);  // no overflow in the midpoint
  ASSERT_TRUE(sync.estimate());
  EXPECT_EQ(sync.estimate()->server_to_client_offset_ns, big - 2 - 7);
}

}  // namespace
}  // namespace telesphere::link
