// SPDX-License-Identifier: MIT
/// @brief LossModel: the loss rate and burst length asked for, seeded and repeatable.
#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "app/bench/impairment/loss_model.h"

namespace telesphere::bench::impairment {
namespace {

struct Measured {
  double loss_fraction = 0;
  double mean_burst = 0;
};

Measured measure(LossModel& model, int packets) {
  int lost = 0, bursts = 0;
  bool previous = false;
  for (int i = 0; i < packets; ++i) {
    const bool now = model.nextLost();
    lost += now;
    bursts += now && !previous;
    previous = now;
  }
  return {static_cast<double>(lost) / packets, bursts ? static_cast<double>(lost) / bursts : 0.0};
}

TEST(LossModel, NoLossLosesNothing) {
  LossModel model;
  EXPECT_EQ(measure(model, 100'000).loss_fraction, 0.0);
}

TEST(LossModel, IndependentLossHasTheAskedRateAndBurstsNearOne) {
  LossModel model({0.01, 1, 7});
  const Measured m = measure(model, 400'000);
  // Binomial: σ = sqrt(0.01 · 0.99 / 4e5) = 1.6e-4; 5 σ.
  EXPECT_NEAR(m.loss_fraction, 0.01, 8e-4);
  EXPECT_NEAR(m.mean_burst, 1.0 / 0.99, 0.02);
}

TEST(LossModel, BurstsHaveTheAskedMeanLengthAndRate) {
  // Long links' few percent, and heavy loss where good → bad differs most from p/b.
  for (const auto& [loss, burst] : {std::pair{0.02, 2.0}, {0.02, 5.0}, {0.02, 20.0}, {0.3, 3.0}}) {
    LossModel model({loss, burst, 11});
    const Measured m = measure(model, 2'000'000);
    EXPECT_NEAR(m.loss_fraction, loss, loss * 0.1) << loss << " in bursts of " << burst;
    EXPECT_NEAR(m.mean_burst, burst, burst * 0.1) << loss << " in bursts of " << burst;
    EXPECT_DOUBLE_EQ(model.badToGood(), 1.0 / burst);
  }
}

TEST(LossModel, TheSameSeedLosesTheSamePackets) {
  LossModel a({0.05, 3, 42}), b({0.05, 3, 42}), c({0.05, 3, 43});
  std::vector<bool> la, lb, lc;
  for (int i = 0; i < 10'000; ++i) {
    la.push_back(a.nextLost());
    lb.push_back(b.nextLost());
    lc.push_back(c.nextLost());
  }
  EXPECT_EQ(la, lb);
  EXPECT_NE(la, lc);
}

TEST(LossModel, ImpossibleOptionsAreNamed) {
  EXPECT_TRUE(checkLossOptions({0.5, 1, 1}).empty());
  EXPECT_NE(checkLossOptions({1.0, 1, 1}).find("[0, 1)"), std::string::npos);
  EXPECT_NE(checkLossOptions({-0.1, 1, 1}).find("[0, 1)"), std::string::npos);
  EXPECT_NE(checkLossOptions({0.1, 0.5, 1}).find("≥ 1 packet"), std::string::npos);
  // 90 % loss in bursts of 2 would need good → bad > 1.
  EXPECT_NE(checkLossOptions({0.9, 2, 1}).find("cannot be made"), std::string::npos);
  EXPECT_TRUE(checkLossOptions({0.6, 2, 1}).empty());
}

}  // namespace
}  // namespace telesphere::bench::impairment
