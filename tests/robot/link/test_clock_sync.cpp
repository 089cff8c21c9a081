// SPDX-License-Identifier: MIT
/// @brief ClockSync on synthetic exchanges with a known offset and asymmetric queueing delays,
///        a queue that stands on one leg for minutes (an Internet downlink filled by a bulk
///        flow), and clocks that drift apart.
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
  EXPECT_LE(std::abs(e->server_to_client_offset_ns - offset), e->uncertainty_ns);
  EXPECT_LT(e->uncertainty_ns, 3'000'000);  // half the best round trip, and the drift its age allows
  EXPECT_LT(e->round_trip_ns, 1'000'000);  // the best of the last 32 exchanges
  EXPECT_EQ(*sync.serverToClient(0), e->server_to_client_offset_ns);
}

/// One exchange every 200 ms (LinkClient's ping period) with up/down one-way delays; the client
/// clock runs `drift` faster than the server's. Returns the estimate's offset error at the end.
struct Exchanges {
  ClockSync sync;
  std::int64_t t_server = 5'000'000'000;
  std::int64_t offset = -2'000'000'000;  ///< t_client = t_server·(1 + drift) + offset
  double drift = 0;
  std::mt19937 rng{3};
  std::int64_t client(std::int64_t server) const { return server + std::int64_t(double(server) * drift) + offset; }
  /// `seconds` of exchanges over legs of `up_ns` and `down_ns` plus up to 5 ms of jitter each.
  void run(double seconds, std::int64_t up_ns, std::int64_t down_ns) {
    std::uniform_int_distribution<std::int64_t> jitter(0, 5'000'000);
    for (int i = 0; i < int(seconds * 5); ++i) {
      const std::int64_t send = t_server;
      const std::int64_t at_server = send + up_ns + jitter(rng);
      const std::int64_t back = at_server + down_ns + jitter(rng);
      sync.addSample(client(send), at_server, client(back));
      t_server += 200'000'000;
    }
  }
  /// How far the estimate maps the server's present from the client's, ns.
  std::int64_t errorNs() const { return *sync.serverToClient(t_server) - client(t_server); }
};

TEST(ClockSync, HoldsTheOffsetWhileAQueueStandsOnOneLegForMinutes) {
  // 200 ms RTT, then 400 ms of queue on the downlink for 5 minutes: each exchange's midpoint is
  // then 200 ms off. The offset found before the queue must hold (a one-way delay read through
  // it, e.g. a head target's age, would otherwise be 200 ms wrong).
  Exchanges x;
  x.run(20, 100'000'000, 100'000'000);
  EXPECT_LT(std::abs(x.errorNs()), 5'000'000);
  x.run(300, 100'000'000, 500'000'000);
  EXPECT_LT(std::abs(x.errorNs()), 5'000'000) << "the standing queue moved the offset";
  EXPECT_LT(x.sync.estimate()->uncertainty_ns, 150'000'000);  // a sample from before the queue…
  EXPECT_GE(x.sync.estimate()->round_trip_ns, 600'000'000);   // …while the round trip is today's
  // Once the queue drains, the estimate is as good as before.
  x.run(20, 100'000'000, 100'000'000);
  EXPECT_LT(std::abs(x.errorNs()), 5'000'000);
}

TEST(ClockSync, FollowsClocksThatDriftApart) {
  // 50 ppm (two crystals at the edges of their tolerance), 20 ms RTT, 10 minutes: an estimate
  // that kept its first sample would be 30 ms off by then.
  Exchanges x;
  x.drift = 50e-6;
  for (int minute = 0; minute < 10; ++minute) {
    x.run(60, 10'000'000, 10'000'000);
    EXPECT_LT(std::abs(x.errorNs()), 5'000'000) << "after " << minute + 1 << " min";
  }
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
