// SPDX-License-Identifier: MIT
/// @brief Stereo pairing by capture timestamp: hardware-triggered pairs, jittered free-running
///        streams against a brute-force reference, any interleaving of arrivals, drops counted
///        by reason, and never a pair further apart than the tolerance (seeded random streams);
///        two synthetic cameras on one simulated clock paired through StereoPairSource.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "robot/clock/sim_clock.h"
#include "robot/stereo/stereo_pairer.h"
#include "robot/cameras/synthetic_camera.h"
#include "robot/cameras/synthetic_scene.h"

namespace telesphere::robot {
namespace {

constexpr std::int64_t kMs = 1'000'000;

cameras::CameraFrame frameAt(std::int64_t capture_ns, std::uint64_t sequence) {
  cameras::CameraFrame f;
  f.capture_ns = capture_ns;
  f.sequence = sequence;
  return f;
}

struct Arrival {
  cameras::CameraSide side;
  cameras::CameraFrame frame;
};

/// A free-running stream: frame k at offset + k·period + uniform jitter, each frame missing with
/// probability `loss` (its sequence number is then skipped, as a camera's would be).
std::vector<cameras::CameraFrame> jitteredStream(std::mt19937& rng, int n, std::int64_t period_ns, std::int64_t offset_ns,
                                        std::int64_t jitter_ns, double loss) {
  std::uniform_int_distribution<std::int64_t> jitter(-jitter_ns, jitter_ns);
  std::bernoulli_distribution lost(loss);
  std::vector<cameras::CameraFrame> out;
  for (int k = 0; k < n; ++k) {
    const std::int64_t t = offset_ns + k * period_ns + jitter(rng);
    if (!lost(rng)) out.push_back(frameAt(t, static_cast<std::uint64_t>(k)));
  }
  return out;
}

/// A random merge of the two streams that keeps each side's own order.
std::vector<Arrival> randomInterleaving(std::mt19937& rng, const std::vector<cameras::CameraFrame>& left,
                                        const std::vector<cameras::CameraFrame>& right) {
  std::vector<Arrival> out;
  std::size_t i = 0, j = 0;
  while (i < left.size() || j < right.size()) {
    const bool take_left = j == right.size() || (i < left.size() && std::bernoulli_distribution(0.5)(rng));
    if (take_left)
      out.push_back({cameras::CameraSide::kLeft, left[i++]});
    else
      out.push_back({cameras::CameraSide::kRight, right[j++]});
  }
  return out;
}

/// Arrival by capture time (what two cameras delivering on time give).
std::vector<Arrival> timeOrdered(const std::vector<cameras::CameraFrame>& left, const std::vector<cameras::CameraFrame>& right) {
  std::vector<Arrival> out;
  for (const auto& f : left) out.push_back({cameras::CameraSide::kLeft, f});
  for (const auto& f : right) out.push_back({cameras::CameraSide::kRight, f});
  std::stable_sort(out.begin(), out.end(),
                   [](const Arrival& a, const Arrival& b) { return a.frame.capture_ns < b.frame.capture_ns; });
  return out;
}

using PairKey = std::pair<std::int64_t, std::int64_t>;  // (left capture_ns, right capture_ns)

std::set<PairKey> runPairer(stereo::StereoPairer& pairer, const std::vector<Arrival>& arrivals) {
  std::set<PairKey> pairs;
  std::set<std::int64_t> used_left, used_right;
  for (const Arrival& a : arrivals) {
    if (auto p = pairer.push(a.side, a.frame)) {
      EXPECT_LE(std::abs(p->skewNs()), pairer.options().tolerance_ns);
      EXPECT_TRUE(used_left.insert(p->left.capture_ns).second) << "left frame paired twice";
      EXPECT_TRUE(used_right.insert(p->right.capture_ns).second) << "right frame paired twice";
      pairs.insert({p->left.capture_ns, p->right.capture_ns});
    }
  }
  pairer.flush();
  return pairs;
}

TEST(StereoPairer, HardwareTriggeredFramesPairExactlyInAnyInterleaving) {
  std::vector<cameras::CameraFrame> left, right;
  for (std::uint64_t k = 0; k < 40; ++k) {
    left.push_back(frameAt(1'000 * kMs + static_cast<std::int64_t>(k) * 22 * kMs, k + 7));
    right.push_back(frameAt(1'000 * kMs + static_cast<std::int64_t>(k) * 22 * kMs, k + 7));
  }
  std::mt19937 rng(5);
  stereo::StereoPairerOptions options;
  options.tolerance_ns = 0;
  options.match_sequence = true;
  options.max_waiting = 64;
  std::vector<std::vector<Arrival>> orders = {timeOrdered(left, right), randomInterleaving(rng, left, right)};
  std::vector<Arrival> all_left_first;
  for (const auto& f : left) all_left_first.push_back({cameras::CameraSide::kLeft, f});
  for (const auto& f : right) all_left_first.push_back({cameras::CameraSide::kRight, f});
  orders.push_back(all_left_first);
  for (const auto& order : orders) {
    stereo::StereoPairer pairer(options);
    std::uint64_t matched_sequences = 0;
    for (const Arrival& a : order) {
      if (auto p = pairer.push(a.side, a.frame)) {
        EXPECT_EQ(p->skewNs(), 0);
        matched_sequences += p->left.sequence == p->right.sequence;
      }
    }
    const stereo::StereoPairerStats stats = pairer.stats();
    EXPECT_EQ(stats.pairs, 40u);
    EXPECT_EQ(matched_sequences, 40u);
    EXPECT_EQ(stats.dropped[0].total() + stats.dropped[1].total(), 0u);
    EXPECT_EQ(stats.max_abs_skew_ns, 0);
  }
}

TEST(StereoPairer, EqualTimesWithDifferentSequenceDoNotPairWhenSequencesMustMatch) {
  stereo::StereoPairerOptions options;
  options.tolerance_ns = kMs;
  options.match_sequence = true;
  stereo::StereoPairer pairer(options);
  EXPECT_FALSE(pairer.push(cameras::CameraSide::kLeft, frameAt(100 * kMs, 3)));
  EXPECT_FALSE(pairer.push(cameras::CameraSide::kRight, frameAt(100 * kMs, 4)));
  EXPECT_TRUE(pairer.push(cameras::CameraSide::kRight, frameAt(100 * kMs + kMs / 2, 3)));
  // The right frame with sequence 4 drops once the left stream has moved past it.
  EXPECT_FALSE(pairer.push(cameras::CameraSide::kLeft, frameAt(133 * kMs, 4)));
  const stereo::StereoPairerStats stats = pairer.stats();
  EXPECT_EQ(stats.pairs, 1u);
  EXPECT_EQ(stats.dropped[1].no_partner, 1u);
}

TEST(StereoPairer, MissingFrameDropsItsPartnerAsNoPartner) {
  stereo::StereoPairerOptions options;
  options.tolerance_ns = 5 * kMs;
  stereo::StereoPairer pairer(options);
  EXPECT_FALSE(pairer.push(cameras::CameraSide::kLeft, frameAt(0, 0)));
  EXPECT_TRUE(pairer.push(cameras::CameraSide::kRight, frameAt(2 * kMs, 0)));
  EXPECT_FALSE(pairer.push(cameras::CameraSide::kLeft, frameAt(33 * kMs, 1)));  // its right frame is lost
  EXPECT_EQ(pairer.waiting(cameras::CameraSide::kLeft), 1u);
  // A right frame 6 ms after the left one: outside the tolerance, never paired.
  EXPECT_FALSE(pairer.push(cameras::CameraSide::kRight, frameAt(39 * kMs, 2)));
  EXPECT_EQ(pairer.waiting(cameras::CameraSide::kLeft), 0u);  // 39 − 33 > 5: no partner can come
  EXPECT_EQ(pairer.stats().dropped[0].no_partner, 1u);
  EXPECT_TRUE(pairer.push(cameras::CameraSide::kLeft, frameAt(41 * kMs, 2)));  // nearest within 5 ms
  EXPECT_FALSE(pairer.push(cameras::CameraSide::kLeft, frameAt(66 * kMs, 3)));
  pairer.flush();
  const stereo::StereoPairerStats stats = pairer.stats();
  EXPECT_EQ(stats.pairs, 2u);
  EXPECT_EQ(stats.dropped[0].flushed, 1u);
  EXPECT_EQ(stats.dropped[1].total(), 0u);
  EXPECT_EQ(stats.max_abs_skew_ns, 2 * kMs);
}

TEST(StereoPairer, TakesTheNearestCandidate) {
  stereo::StereoPairerOptions options;
  options.tolerance_ns = 10 * kMs;
  options.max_waiting = 8;
  stereo::StereoPairer pairer(options);
  EXPECT_FALSE(pairer.push(cameras::CameraSide::kRight, frameAt(95 * kMs, 0)));  // 8 ms from the left one
  EXPECT_FALSE(pairer.push(cameras::CameraSide::kRight, frameAt(105 * kMs, 1)));  // 2 ms: nearer
  const auto p = pairer.push(cameras::CameraSide::kLeft, frameAt(103 * kMs, 0));
  ASSERT_TRUE(p);
  EXPECT_EQ(p->right.capture_ns, 105 * kMs);
  EXPECT_EQ(p->skewNs(), 2 * kMs);
}

TEST(StereoPairer, OverflowDropsTheOldestWaitingFrame) {
  stereo::StereoPairerOptions options;
  options.tolerance_ns = kMs;
  options.max_waiting = 3;
  stereo::StereoPairer pairer(options);
  for (int k = 0; k < 5; ++k) EXPECT_FALSE(pairer.push(cameras::CameraSide::kLeft, frameAt(k * 20 * kMs, k)));
  EXPECT_EQ(pairer.waiting(cameras::CameraSide::kLeft), 3u);
  EXPECT_EQ(pairer.stats().dropped[0].overflow, 2u);
  // The oldest two are gone: the right frame at 0 finds nothing; the one at 40 ms pairs.
  EXPECT_FALSE(pairer.push(cameras::CameraSide::kRight, frameAt(0, 0)));
  EXPECT_TRUE(pairer.push(cameras::CameraSide::kRight, frameAt(40 * kMs, 2)));
}

/// Brute force: with a tolerance below half the smallest spacing of both streams each frame has
/// at most one partner, so the pairs are exactly those within the tolerance.
std::set<PairKey> referencePairs(const std::vector<cameras::CameraFrame>& left, const std::vector<cameras::CameraFrame>& right,
                                 std::int64_t tolerance_ns) {
  std::set<PairKey> out;
  for (const auto& l : left)
    for (const auto& r : right)
      if (std::abs(l.capture_ns - r.capture_ns) <= tolerance_ns) out.insert({l.capture_ns, r.capture_ns});
  return out;
}

TEST(StereoPairer, JitteredStreamsPairAsTheReferenceInAnyInterleaving) {
  std::mt19937 rng(20261122);
  for (int trial = 0; trial < 20; ++trial) {
    // 30 Hz free-running cameras, right 4 ms behind, ±3 ms jitter, 5 % of frames lost each.
    const auto left = jitteredStream(rng, 200, 33'333'333, 0, 3 * kMs, 0.05);
    const auto right = jitteredStream(rng, 200, 33'333'333, 4 * kMs, 3 * kMs, 0.05);
    stereo::StereoPairerOptions options;
    options.tolerance_ns = 8 * kMs;  // < (33.3 − 6)/2 ms
    options.max_waiting = 512;       // any interleaving, even one side entirely first
    const std::set<PairKey> expected = referencePairs(left, right, options.tolerance_ns);
    ASSERT_GT(expected.size(), 150u);
    for (int order = 0; order < 3; ++order) {
      SCOPED_TRACE("trial " + std::to_string(trial) + " order " + std::to_string(order));
      const std::vector<Arrival> arrivals =
          order == 0 ? timeOrdered(left, right) : randomInterleaving(rng, left, right);
      stereo::StereoPairer pairer(options);
      const std::set<PairKey> pairs = runPairer(pairer, arrivals);
      EXPECT_EQ(pairs, expected);
      const stereo::StereoPairerStats stats = pairer.stats();
      EXPECT_EQ(stats.pairs, expected.size());
      EXPECT_EQ(stats.pairs + stats.dropped[0].total(), left.size());
      EXPECT_EQ(stats.pairs + stats.dropped[1].total(), right.size());
      EXPECT_LE(stats.max_abs_skew_ns, options.tolerance_ns);
      if (order == 0) {
        // Arriving on time, unpaired frames leave as soon as the other side passes them.
        EXPECT_EQ(stats.dropped[0].overflow + stats.dropped[1].overflow, 0u);
        EXPECT_LE(stats.dropped[0].flushed + stats.dropped[1].flushed, 4u);
      }
    }
  }
}

TEST(StereoPairer, RandomStreamsNeverPairBeyondTheTolerance) {
  // Wide tolerances (several candidates per frame), different rates, frames of a side arriving
  // out of order within reorder_ns, small queues: whatever happens, no pair exceeds the
  // tolerance, no frame is used twice, and every frame is either paired or counted as dropped.
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const std::int64_t period_l = std::uniform_int_distribution<std::int64_t>(5, 40)(rng) * kMs;
    const std::int64_t period_r = std::uniform_int_distribution<std::int64_t>(5, 40)(rng) * kMs;
    const std::int64_t jitter = std::uniform_int_distribution<std::int64_t>(0, 10)(rng) * kMs;
    auto left = jitteredStream(rng, 100, period_l, 0, jitter, 0.1);
    auto right = jitteredStream(rng, 100, period_r, 3 * kMs, jitter, 0.1);
    stereo::StereoPairerOptions options;
    options.tolerance_ns = std::uniform_int_distribution<std::int64_t>(0, 30)(rng) * kMs;
    options.reorder_ns = 2 * jitter;
    options.max_waiting = std::uniform_int_distribution<std::size_t>(1, 10)(rng);
    options.match_sequence = trial % 5 == 0;
    stereo::StereoPairer pairer(options);
    std::vector<Arrival> arrivals = randomInterleaving(rng, left, right);
    // Some neighbours swapped: a side's own frames now and then arrive out of order too.
    for (std::size_t i = 0; i + 1 < arrivals.size(); ++i)
      if (std::bernoulli_distribution(0.2)(rng)) std::swap(arrivals[i], arrivals[i + 1]);
    const std::set<PairKey> pairs = runPairer(pairer, arrivals);
    const stereo::StereoPairerStats stats = pairer.stats();
    EXPECT_EQ(stats.pairs, pairs.size());
    EXPECT_EQ(stats.pairs + stats.dropped[0].total(), left.size()) << "trial " << trial;
    EXPECT_EQ(stats.pairs + stats.dropped[1].total(), right.size()) << "trial " << trial;
    EXPECT_LE(stats.max_abs_skew_ns, options.tolerance_ns);
    EXPECT_EQ(pairer.waiting(cameras::CameraSide::kLeft) + pairer.waiting(cameras::CameraSide::kRight), 0u);
  }
}

TEST(StereoPairSource, PairsTwoSyntheticCamerasTriggeredTogether) {
  // Two synthetic cameras 64 mm apart on one simulated clock, same rate and phase: a hardware
  // trigger. Every pair has equal capture times and sequence numbers, and the images differ
  // (parallax).
  clock::SimClock clock(1);  // the first tick is then tick 1
  auto scene = std::make_shared<cameras::SyntheticScene>(cameras::defaultScene());
  Eigen::VectorXd p(6);
  p << 39.4, 39.4, 79.5, 63.5, -0.18, 0.59;
  const auto camera = *calib::GenericCamera::create("ds", p);
  const auto pose_l = [](std::int64_t t_ns) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(0.3 * static_cast<double>(t_ns) * 1e-9, Eigen::Vector3d::UnitZ()) *
                 (Eigen::Matrix3d() << 0, 0, 1, -1, 0, 0, 0, -1, 0).finished();
    T.translation() = cameras::DefaultSceneLayout{}.head_position;
    return T;
  };
  const auto pose_r = [pose_l](std::int64_t t_ns) {
    return pose_l(t_ns) * Eigen::Translation3d(0.064, 0, 0);  // T_cam_l_cam_r of the sim rig
  };
  cameras::SyntheticCameraOptions options;
  options.fps = 45.0;
  options.exposure_us = 0;  // delivered at the tick: the threads may look at the clock only then
  options.name = "synthetic-left";
  cameras::SyntheticCamera left(camera, 160, 128, scene, pose_l, clock, options);
  options.name = "synthetic-right";
  cameras::SyntheticCamera right(camera, 160, 128, scene, pose_r, clock, options);
  stereo::StereoPairerOptions pairing;
  pairing.tolerance_ns = kMs;
  pairing.match_sequence = true;
  stereo::StereoPairSource source(left, right, pairing);
  ASSERT_TRUE(left.start(nullptr));
  ASSERT_TRUE(right.start(nullptr));
  source.start();
  for (std::uint64_t k = 1; k <= 4; ++k) {
    clock.set(static_cast<std::int64_t>(k) * left.periodNs());
    const auto pair = source.nextPair(std::chrono::seconds(30));
    ASSERT_TRUE(pair) << "pair " << k;
    EXPECT_EQ(pair->left.capture_ns, static_cast<std::int64_t>(k) * left.periodNs());
    EXPECT_EQ(pair->skewNs(), 0);
    EXPECT_EQ(pair->left.sequence, pair->right.sequence);
    EXPECT_EQ(pair->left.sequence, k - 1);
    EXPECT_FALSE(*pair->left.pixels == *pair->right.pixels);
  }
  source.stop();
  EXPECT_FALSE(source.nextPair(std::chrono::milliseconds(0)));
  left.stop();
  right.stop();
  const stereo::StereoPairerStats stats = source.stats();
  EXPECT_EQ(stats.pairs, 4u);
  EXPECT_EQ(stats.dropped[0].total() + stats.dropped[1].total(), 0u);
}

}  // namespace
}  // namespace telesphere::robot
