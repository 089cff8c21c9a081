// SPDX-License-Identifier: MIT
/// @brief TelemetryModel: every sample lands at its source time mapped into the console clock
///        (robot stamps by the console's offset, XR stamps through the XR app's offset too),
///        stage latencies and speeds are computed right, the media path's and the scene proxy's
///        series land at their batch times, lost and unsynced batches are counted,
///        and ten minutes of telemetry at full rate (simulated) keep memory flat.
#include <gtest/gtest.h>

#include <cmath>

#include "console/telemetry/telemetry_model.h"
#include "robot/link/link_pose.h"

namespace telesphere::console::telemetry {
namespace {

constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kS = 1'000'000'000;

link::proto::Envelope robotBatch(std::uint64_t batch) {
  link::proto::Envelope e;
  e.mutable_robot_telemetry()->set_batch(batch);
  return e;
}

link::proto::Envelope xrBatch(std::uint64_t batch, std::int64_t robot_to_xr_ns) {
  link::proto::Envelope e;
  auto* t = e.mutable_xr_telemetry();
  t->set_batch(batch);
  t->set_clock_synced(true);
  t->set_robot_to_xr_offset_ns(robot_to_xr_ns);
  return e;
}

TEST(TelemetryModel, RobotSamplesLandAtTheirCaptureTimeInTheConsoleClock) {
  SeriesStore store;
  const std::int64_t origin = 100 * kS;  // console clock when the console started
  TelemetryModel model(store, origin);
  const std::int64_t robot_to_console = 7 * kS + 123 * kMs;  // another machine's clock
  auto e = robotBatch(1);
  auto* f = e.mutable_robot_telemetry()->add_frames();
  f->set_capture_ns(95 * kS);  // robot clock
  f->set_encoded_ns(95 * kS + 18 * kMs);
  f->set_sent_ns(95 * kS + 19 * kMs);
  model.ingest(e, robot_to_console);
  const TimeSeries* encoded = store.find(series::kLatencyStages[0]);
  const TimeSeries* sent = store.find(series::kLatencyStages[1]);
  ASSERT_TRUE(encoded && sent);
  ASSERT_EQ(encoded->size(), 1u);
  // 95 s robot = 102.123 s console = 2.123 s after the console started.
  EXPECT_NEAR((*encoded)[0].t, 2.123, 1e-9);
  EXPECT_NEAR((*encoded)[0].v, 18.0, 1e-9);
  EXPECT_NEAR((*sent)[0].t, 2.123, 1e-9);
  EXPECT_NEAR((*sent)[0].v, 19.0, 1e-9);
  // The same batch taken later (another receive time) lands at the same place: no receive time.
  model.ingest(e, robot_to_console);
  EXPECT_NEAR((*encoded)[1].t, (*encoded)[0].t, 0);
}

TEST(TelemetryModel, XrStagesGoThroughBothOffsets) {
  SeriesStore store;
  TelemetryModel model(store, 0);
  const std::int64_t robot_to_console = -2 * kS;
  const std::int64_t robot_to_xr = 40 * kS;  // the XR app's clock runs 40 s ahead of the robot's
  auto e = xrBatch(1, robot_to_xr);
  auto* f = e.mutable_xr_telemetry()->add_frames();
  const std::int64_t capture = 10 * kS;  // robot clock
  f->set_display_ns(capture + robot_to_xr + 45 * kMs);
  f->set_render_ms(7.5);
  f->set_missed(2);
  f->set_stereo_sequence(3);
  f->set_new_image(true);
  f->set_eye_camera_distance_m(0.034);
  auto* s = f->mutable_stamps();
  s->set_capture_ns(capture);
  s->set_encoded_ns(capture + 18 * kMs);
  s->set_sent_ns(capture + 19 * kMs);
  s->set_received_ns(capture + robot_to_xr + 21 * kMs);  // XR clock from here on
  s->set_decoded_ns(capture + robot_to_xr + 33 * kMs);
  s->set_uploaded_ns(capture + robot_to_xr + 37 * kMs);
  s->set_displayed_ns(capture + robot_to_xr + 45 * kMs);
  model.ingest(e, robot_to_console);
  const double capture_plot = double(capture + robot_to_console) * 1e-9;  // 8 s
  const double expected_ms[] = {21, 33, 37, 45};
  for (int i = 0; i < 4; ++i) {
    const TimeSeries* stage = store.find(series::kLatencyStages[2 + i]);
    ASSERT_TRUE(stage) << i;
    ASSERT_EQ(stage->size(), 1u);
    EXPECT_NEAR((*stage)[0].t, capture_plot, 1e-9) << i;
    EXPECT_NEAR((*stage)[0].v, expected_ms[i], 1e-9) << i;
  }
  // Per-frame series are at the display time, mapped XR → robot → console.
  const TimeSeries* frame_ms = store.find(series::kXrFrameMs);
  ASSERT_TRUE(frame_ms);
  EXPECT_NEAR((*frame_ms)[0].t, capture_plot + 0.045, 1e-9);
  EXPECT_EQ((*frame_ms)[0].v, 7.5);
  EXPECT_EQ((*store.find(series::kXrMissed))[0].v, 2.0);
  EXPECT_NEAR((*store.find(series::kDeltaS))[0].v, 3.4, 1e-12);
  // The newest frame says whether it showed a frame without a measured camera pose.
  ASSERT_TRUE(model.xrUnmeasuredPose());
  EXPECT_FALSE(model.xrUnmeasuredPose()->shown_dimmed);
  auto e2 = xrBatch(2, robot_to_xr);
  auto* dimmed = e2.mutable_xr_telemetry()->add_frames();
  dimmed->set_display_ns(capture + robot_to_xr + 62 * kMs);
  dimmed->set_pose_unmeasured(true);
  model.ingest(e2, robot_to_console);
  EXPECT_TRUE(model.xrUnmeasuredPose()->shown_dimmed);
  EXPECT_EQ(model.counts().xr_frames_unmeasured, 1u);
}

TEST(TelemetryModel, SpeedsFromConsecutivePosesAndHeadLatencyAtTheSampleTime) {
  SeriesStore store;
  TelemetryModel model(store, 0);
  // Operator: 0.5 m/s along x, poses 10 ms apart.
  auto x = xrBatch(1, 0);
  for (int i = 0; i < 5; ++i) {
    auto* f = x.mutable_xr_telemetry()->add_frames();
    f->set_display_ns(1 * kS + i * 10 * kMs);
    f->set_head_valid(true);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation().x() = 0.005 * i;
    link::toLinkPose(T, f->mutable_t_vr_hmd());
    f->set_eye_camera_distance_m(-1);  // unknown: no Δs sample
  }
  model.ingest(x, 0);
  const TimeSeries* v_op = store.find(series::kVOp);
  ASSERT_TRUE(v_op);
  ASSERT_EQ(v_op->size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR((*v_op)[i].v, 50.0, 1e-6);
  EXPECT_TRUE(store.find(series::kDeltaS)->empty());
  EXPECT_EQ(model.recentHeadPoses().size(), 5u);

  // Robot: measured head 0.2 m/s along z; a head target sampled 6 ms before it was taken.
  auto r = robotBatch(1);
  for (int i = 0; i < 3; ++i) {
    auto* tick = r.mutable_robot_telemetry()->add_ticks();
    tick->set_t_ns(2 * kS + i * 10 * kMs);
    tick->set_joint_state_ns(2 * kS + i * 10 * kMs - kMs);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation().z() = 0.002 * i;
    link::toLinkPose(T, tick->mutable_t_robot_head_measured());
    tick->set_target_new(true);
    tick->set_target_t_ns(tick->t_ns() - 6 * kMs);
    tick->set_target_arrival_ns(tick->t_ns());
  }
  model.ingest(r, 0);
  const TimeSeries* v_rob = store.find(series::kVRob);
  ASSERT_TRUE(v_rob);
  ASSERT_EQ(v_rob->size(), 2u);
  EXPECT_NEAR((*v_rob)[0].v, 20.0, 1e-6);
  EXPECT_NEAR((*v_rob)[0].t, 2.009, 1e-9);  // at the joint state's time
  const TimeSeries* latency = store.find(series::kHeadLatency);
  ASSERT_EQ(latency->size(), 3u);
  EXPECT_NEAR((*latency)[0].v, 6.0, 1e-9);
  EXPECT_NEAR((*latency)[0].t, 1.994, 1e-9);  // at the sample time, not the arrival
}

TEST(TelemetryModel, TheMediaPathsSamplesAtTheirSendTimeAndTheReceiversCountsAsRates) {
  SeriesStore store;
  TelemetryModel model(store, 100 * kS);
  const std::int64_t robot_to_console = 7 * kS;  // robot 95 s = console 102 s = plot 2 s
  auto e = robotBatch(1);
  auto* f = e.mutable_robot_telemetry()->add_frames();
  f->set_capture_ns(94 * kS);
  f->set_encoded_ns(94 * kS + 500 * kMs);
  f->set_sent_ns(95 * kS);
  auto* m = f->mutable_media();
  m->set_receiver(true);
  m->set_target_mbit(18.5);
  m->set_delivered_mbit(17.25);
  m->set_cap_mbit(20);
  m->set_rtt_ms(103.5);
  m->set_queue_delay_ms(4);
  m->set_loss_fraction(0.0125);
  m->set_fps(15);
  m->set_scale(0.5);
  m->set_quality(70);
  // A second frame: no receiver (nothing goes out), no cap, no round trip yet.
  auto* g = e.mutable_robot_telemetry()->add_frames();
  *g = *f;
  g->set_sent_ns(96 * kS);
  g->mutable_media()->set_receiver(false);
  g->mutable_media()->set_cap_mbit(0);
  g->mutable_media()->set_rtt_ms(-1);
  model.ingest(e, robot_to_console);
  const auto one = [&](const char* name, std::size_t count, double t, double v) {
    const TimeSeries* series = store.find(name);
    ASSERT_TRUE(series) << name;
    ASSERT_EQ(series->size(), count) << name;
    EXPECT_NEAR((*series)[0].t, t, 1e-9) << name;
    EXPECT_NEAR((*series)[0].v, v, 1e-9) << name;
  };
  one(series::kLinkTargetMbit, 1, 2.0, 18.5);
  one(series::kLinkDeliveredMbit, 1, 2.0, 17.25);
  one(series::kLinkCapMbit, 1, 2.0, 20.0);
  one(series::kLinkRttMs, 1, 2.0, 103.5);
  one(series::kLinkQueueMs, 1, 2.0, 4.0);
  one(series::kLinkLossPct, 1, 2.0, 1.25);
  one(series::kLinkFps, 2, 2.0, 15.0);  // the stream's settings hold with or without a receiver
  one(series::kLinkScalePct, 2, 2.0, 50.0);
  one(series::kLinkQuality, 2, 2.0, 70.0);
  EXPECT_EQ(TelemetryModel::infoOf(series::kLinkLossPct).unit, "%");

  // The receiver's counts: rates between batches, at the XR batch time; a restarted XR app's
  // counts start again (no negative rate).
  const std::int64_t robot_to_xr = -3 * kS;  // xr 97 s = robot 100 s = plot 7 s
  const auto counts = [&](std::uint64_t batch, std::int64_t xr_ns, std::uint64_t repaired, std::uint64_t concealed,
                          std::uint64_t lost) {
    auto x = xrBatch(batch, robot_to_xr);
    auto* c = x.mutable_xr_telemetry()->mutable_media();
    c->set_t_ns(xr_ns);
    c->set_datagrams(1000 * batch);
    c->set_chunks_repaired(repaired);
    c->set_bands_concealed(concealed);
    c->set_frames_lost(lost);
    model.ingest(x, robot_to_console);
  };
  counts(1, 97 * kS, 10, 2, 0);
  EXPECT_EQ(store.find(series::kLinkRepairedPerS)->size(), 0u) << "one count is no rate";
  counts(2, 97 * kS + 500 * kMs, 30, 3, 1);
  one(series::kLinkRepairedPerS, 1, 7.5, 40.0);
  one(series::kLinkConcealedPerS, 1, 7.5, 2.0);
  one(series::kLinkLostFramesPerS, 1, 7.5, 2.0);
  counts(1, 98 * kS, 0, 0, 0);  // the XR app restarted
  counts(2, 99 * kS, 5, 0, 0);
  const TimeSeries& repaired = *store.find(series::kLinkRepairedPerS);
  ASSERT_EQ(repaired.size(), 2u);
  EXPECT_NEAR(repaired[1].t, 9.0, 1e-9);
  EXPECT_NEAR(repaired[1].v, 5.0, 1e-9);
}

TEST(TelemetryModel, TheScenesProxyRadiiAndDepthConfidenceAtTheBatchTime) {
  SeriesStore store;
  TelemetryModel model(store, 100 * kS);
  const std::int64_t robot_to_console = 7 * kS, robot_to_xr = -3 * kS;  // xr 97 s = plot 7 s
  EXPECT_FALSE(model.xrDepthProxy()) << "nothing before a batch says";
  // The fixed sphere, no estimate yet: the radii only.
  auto x = xrBatch(1, robot_to_xr);
  auto* d = x.mutable_xr_telemetry()->mutable_depth();
  d->set_t_ns(97 * kS);
  d->set_proxy(link::proto::DEPTH_PROXY_FIXED);
  d->add_radius_m(1.0);
  d->add_radius_m(1.0);
  d->set_estimate_age_ms(-1);
  model.ingest(x, robot_to_console);
  EXPECT_EQ(model.xrDepthProxy(), link::proto::DEPTH_PROXY_FIXED);
  ASSERT_EQ(store.find(series::kDepthRadiusLeftM)->size(), 1u);
  EXPECT_NEAR((*store.find(series::kDepthRadiusLeftM))[0].t, 7.0, 1e-9);
  EXPECT_EQ(store.find(series::kDepthMatchedLeftPct)->size(), 0u) << "no estimate, no confidence";
  EXPECT_EQ(store.find(series::kDepthAgeMs)->size(), 0u);
  // The grid from the stereo depth: each eye's radius, the confidence in %, age and cost.
  x = xrBatch(2, robot_to_xr);
  d = x.mutable_xr_telemetry()->mutable_depth();
  d->set_t_ns(97 * kS + 100 * kMs);
  d->set_proxy(link::proto::DEPTH_PROXY_GRID);
  d->add_radius_m(0.52);
  d->add_radius_m(std::nan(""));  // a peer's nonsense is not plotted
  d->add_matched_fraction(0.78);
  d->add_matched_fraction(0.81);
  d->set_estimate_age_ms(61.5);
  d->set_sweep_ms(14.25);
  model.ingest(x, robot_to_console);
  EXPECT_EQ(model.xrDepthProxy(), link::proto::DEPTH_PROXY_GRID);
  const auto last = [&](const char* name) { return store.find(name)->empty() ? -1.0 : (*store.find(name))[store.find(name)->size() - 1].v; };
  EXPECT_DOUBLE_EQ(last(series::kDepthRadiusLeftM), 0.52);
  EXPECT_EQ(store.find(series::kDepthRadiusRightM)->size(), 1u);
  EXPECT_NEAR(last(series::kDepthMatchedLeftPct), 78.0, 1e-9);
  EXPECT_NEAR(last(series::kDepthMatchedRightPct), 81.0, 1e-9);
  EXPECT_DOUBLE_EQ(last(series::kDepthAgeMs), 61.5);
  EXPECT_DOUBLE_EQ(last(series::kDepthSweepMs), 14.25);
  EXPECT_NEAR((*store.find(series::kDepthAgeMs))[0].t, 7.1, 1e-9);
  EXPECT_EQ(TelemetryModel::infoOf(series::kDepthRadiusLeftM).unit, "m");
  EXPECT_EQ(TelemetryModel::infoOf(series::kDepthMatchedLeftPct).unit, "%");
}

TEST(TelemetryModel, CountsLostAndUnsyncedBatches) {
  SeriesStore store;
  TelemetryModel model(store, 0);
  for (std::uint64_t b : {1, 2, 5, 6}) model.ingest(robotBatch(b), 0);
  EXPECT_EQ(model.counts().robot_batches_lost, 2u);
  model.robotRestarted();
  model.ingest(robotBatch(1), 0);  // a new robot process counts from 1: nothing lost
  EXPECT_EQ(model.counts().robot_batches_lost, 2u);
  model.ingest(robotBatch(2), std::nullopt);  // no clock offset yet
  EXPECT_EQ(model.counts().unsynced_batches, 1u);
  auto x = xrBatch(1, 0);
  x.mutable_xr_telemetry()->set_clock_synced(false);
  x.mutable_xr_telemetry()->add_frames()->set_render_ms(3);
  model.ingest(x, 0);
  EXPECT_EQ(model.counts().unsynced_batches, 2u);
  EXPECT_TRUE(store.find(series::kXrFrameMs)->empty());
  model.ingest(xrBatch(4, 0), 0);
  EXPECT_EQ(model.counts().xr_batches_lost, 2u);
  model.ingest(xrBatch(1, 0), 0);  // the XR app restarted
  EXPECT_EQ(model.counts().xr_batches_lost, 2u);
}

TEST(TelemetryModel, TenMinutesAtFullRateKeepMemoryFlat) {
  // Simulated time: 100 Hz head ticks and 45 Hz frames from the robot in 50 ms batches, 90 Hz
  // XR frames in 100 ms batches, the store trimmed to a 60 s window as the console does.
  SeriesStore store;
  store.setRetention(60.0);
  TelemetryModel model(store, 0);
  std::size_t bytes_at_2min = 0, samples_at_2min = 0, max_samples = 0;
  std::uint64_t robot_batch = 0, xr_batch = 0;
  std::int64_t next_frame = 0;
  std::uint64_t sequence = 0;
  for (std::int64_t t = 0; t < 600 * kS; t += 50 * kMs) {
    auto r = robotBatch(++robot_batch);
    for (int i = 0; i < 5; ++i) {
      auto* tick = r.mutable_robot_telemetry()->add_ticks();
      const std::int64_t at = t + i * 10 * kMs;
      tick->set_t_ns(at);
      tick->set_joint_state_ns(at);
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation().x() = 0.1 * std::sin(double(at) * 1e-9);
      link::toLinkPose(T, tick->mutable_t_robot_head_measured());
      tick->set_target_new(true);
      tick->set_target_t_ns(at - 3 * kMs);
      tick->set_target_arrival_ns(at);
    }
    for (; next_frame < t + 50 * kMs; next_frame += kS / 45) {
      auto* f = r.mutable_robot_telemetry()->add_frames();
      f->set_sequence(++sequence);
      f->set_capture_ns(next_frame);
      f->set_encoded_ns(next_frame + 18 * kMs);
      f->set_sent_ns(next_frame + 19 * kMs);
    }
    model.ingest(r, 0);
    if (t % (100 * kMs) == 0) {
      auto x = xrBatch(++xr_batch, 0);
      for (int i = 0; i < 9; ++i) {
        auto* f = x.mutable_xr_telemetry()->add_frames();
        f->set_display_ns(t + i * (kS / 90));
        f->set_head_valid(true);
        link::toLinkPose(Eigen::Isometry3d::Identity(), f->mutable_t_vr_hmd());
        f->set_render_ms(8);
        f->set_eye_camera_distance_m(0.01);
        f->set_new_image(i % 2 == 0);
        f->mutable_stamps()->set_capture_ns(t);
        f->mutable_stamps()->set_displayed_ns(t + 40 * kMs);
      }
      model.ingest(x, 0);
    }
    store.trim(double(t) * 1e-9, double(t) * 1e-9);
    max_samples = std::max(max_samples, store.totalSamples());
    if (t == 120 * kS) {
      bytes_at_2min = store.bytes();
      samples_at_2min = store.totalSamples();
    }
  }
  EXPECT_GT(samples_at_2min, 60u * (100 * 2 + 45 * 2 + 90 * 4));
  // Flat: the last eight minutes add nothing (within a deque block per series).
  EXPECT_LE(store.bytes(), bytes_at_2min + 12 * 1024);
  EXPECT_LE(max_samples, samples_at_2min * 11 / 10);
  EXPECT_EQ(model.counts().robot_batches_lost, 0u);
  EXPECT_EQ(model.counts().robot_batches, robot_batch);
}

}  // namespace
}  // namespace telesphere::console::telemetry
