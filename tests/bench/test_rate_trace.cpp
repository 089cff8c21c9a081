// SPDX-License-Identifier: MIT
/// @brief RateTrace: serialisation times across steps, zero and unlimited rates, parsing.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "app/bench/impairment/rate_trace.h"

namespace telesphere::bench::impairment {
namespace {

constexpr std::int64_t kNsPerMs = 1'000'000;

TEST(RateTrace, ConstantRateSerialisesAtThatRate) {
  const RateTrace trace = RateTrace::constant(1e6);  // 1 Mbit/s: 10 kbit take 10 ms
  EXPECT_EQ(trace.serialisedBy(0, 10'000), 10 * kNsPerMs);
  EXPECT_EQ(trace.serialisedBy(5 * kNsPerMs, 10'000), 15 * kNsPerMs);
  EXPECT_EQ(trace.serialisedBy(7, 0), 7);
}

TEST(RateTrace, UnlimitedTakesNoTime) {
  const RateTrace trace;
  EXPECT_EQ(trace.serialisedBy(123, 1e12), 123);
  EXPECT_TRUE(std::isinf(trace.bitsPerSecondAt(0)));
}

TEST(RateTrace, APacketSpanningAStepUsesBothRates) {
  std::string error;
  const auto trace = RateTrace::steps(1e6, {{1000 * kNsPerMs, 2e6}}, &error);
  ASSERT_TRUE(trace) << error;
  // 5 kbit at 1 Mbit/s until 1 s, the other 5 kbit at 2 Mbit/s: 2.5 ms more.
  EXPECT_EQ(trace->serialisedBy(995 * kNsPerMs, 10'000), 1000 * kNsPerMs + 2'500'000);
  EXPECT_EQ(trace->bitsPerSecondAt(999 * kNsPerMs), 1e6);
  EXPECT_EQ(trace->bitsPerSecondAt(1000 * kNsPerMs), 2e6);
}

TEST(RateTrace, AZeroRateHoldsPacketsUntilTheNextStep) {
  std::string error;
  const auto outage = RateTrace::steps(1e6, {{100 * kNsPerMs, 0}, {300 * kNsPerMs, 1e6}}, &error);
  ASSERT_TRUE(outage) << error;
  EXPECT_EQ(outage->serialisedBy(150 * kNsPerMs, 10'000), 310 * kNsPerMs);
  // Half of the packet before the outage, the rest after it.
  EXPECT_EQ(outage->serialisedBy(95 * kNsPerMs, 10'000), 305 * kNsPerMs);
  // A link that stays down never delivers.
  const auto down = RateTrace::steps(1e6, {{100 * kNsPerMs, 0}}, &error);
  ASSERT_TRUE(down);
  EXPECT_EQ(down->serialisedBy(150 * kNsPerMs, 8), std::numeric_limits<std::int64_t>::max());
  EXPECT_EQ(RateTrace::constant(0).serialisedBy(0, 8), std::numeric_limits<std::int64_t>::max());
}

TEST(RateTrace, HugeAndTinyRatesAndPackets) {
  // 100 Gbit/s and a 64 kB datagram: 5.24 µs.
  EXPECT_EQ(RateTrace::constant(100e9).serialisedBy(0, 8.0 * 65'507), 5241);
  // 1 bit/s: one byte takes 8 s.
  EXPECT_EQ(RateTrace::constant(1).serialisedBy(0, 8), 8'000'000'000);
}

TEST(RateTrace, SawtoothRampsAndFallsBack) {
  const RateTrace trace = RateTrace::sawtooth(10e6, 20e6, 1000 * kNsPerMs, 100 * kNsPerMs, 3000 * kNsPerMs);
  EXPECT_DOUBLE_EQ(trace.bitsPerSecondAt(0), 10e6);
  EXPECT_DOUBLE_EQ(trace.bitsPerSecondAt(550 * kNsPerMs), 15e6);
  EXPECT_DOUBLE_EQ(trace.bitsPerSecondAt(950 * kNsPerMs), 19e6);
  EXPECT_DOUBLE_EQ(trace.bitsPerSecondAt(1000 * kNsPerMs), 10e6);
  EXPECT_EQ(trace.rateSteps().size(), 30u);
}

TEST(RateTrace, ParsesTheBenchmarksSteps) {
  std::string error;
  const auto trace = RateTrace::parseSteps(100e6, "10:20,20.5:100", &error);
  ASSERT_TRUE(trace) << error;
  ASSERT_EQ(trace->rateSteps().size(), 3u);
  EXPECT_EQ(trace->rateSteps()[1].from_ns, 10'000 * kNsPerMs);
  EXPECT_DOUBLE_EQ(trace->rateSteps()[1].bits_per_s, 20e6);
  EXPECT_EQ(trace->rateSteps()[2].from_ns, 20'500 * kNsPerMs);
}

TEST(RateTrace, BadStepsAreRefusedWithTheStep) {
  std::string error;
  EXPECT_FALSE(RateTrace::parseSteps(1e6, "10:20,5:30", &error));
  EXPECT_NE(error.find("rate step 2"), std::string::npos) << error;
  EXPECT_FALSE(RateTrace::parseSteps(1e6, "10", &error));
  EXPECT_NE(error.find("'10'"), std::string::npos) << error;
  EXPECT_FALSE(RateTrace::parseSteps(1e6, "x:5", &error));
  EXPECT_FALSE(RateTrace::parseSteps(1e6, "3:-1", &error));
  EXPECT_FALSE(RateTrace::parseSteps(1e6, "0:5", &error));
  EXPECT_FALSE(RateTrace::parseSteps(1e6, "2:5x", &error));
  EXPECT_FALSE(RateTrace::parseSteps(1e6, "nan:5", &error));
  EXPECT_FALSE(RateTrace::steps(-1, {}, &error));
}

}  // namespace
}  // namespace telesphere::bench::impairment
