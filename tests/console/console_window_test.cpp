// SPDX-License-Identifier: MIT
/// @brief The console's real Qt widgets (QT_QPA_PLATFORM=offscreen) against real telesphere-robot
///        (simulated arm, synthetic cameras) and telesphere-xr offscreen processes on loopback:
///        waiting for an absent robot without freezing; telemetry plotted at source time; the
///        camera preview; every control reaching the robot and the XR app with its reply shown (the scene proxy
///        followed, its depth plotted and recorded);
///        arm stop and clear with the fault banner; the nominal-pose step end to end (capture,
///        confirm, undo; refused without fresh head poses); robot killed and restarted; XR app
///        gone; a calibration applied live from the "Calibration in use" panel reaching the robot's
///        frames and the XR app, and reverted; a calibration hold shown with its holder and ended
///        by "Release head". Writes screenshots of the main window, each plot and each panel (console/README.md
///        shows them) into $TELESPHERE_SCREENSHOT_DIR or build/console-screenshots.
#include <gtest/gtest.h>

#include <QFileInfo>

#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDir>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QFile>
#include <QProcess>
#include <QPushButton>
#include <QSpinBox>
#include <QTabWidget>
#include <QTableWidget>
#include <QTemporaryDir>
#include <QThread>
#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <functional>

#include "calib/calibration_file.h"
#include "console/calibration/calibration_robot.h"
#include "console/widgets/calibration_in_use_panel.h"
#include "console/widgets/camera_preview_panel.h"
#include "console/telemetry/column_decimator.h"
#include "console/widgets/console_session.h"
#include "console/widgets/console_window.h"
#include "console/widgets/control_panel.h"
#include "console/widgets/fault_banner.h"
#include "console/widgets/health_panel.h"
#include "console/widgets/link_panel.h"
#include "console/telemetry/media_link_series.h"
#include "console/widgets/live_plot.h"
#include "console/widgets/nominal_pose_panel.h"
#include "console/widgets/supervisor_plots.h"
#include "console/telemetry/depth_proxy_series.h"
#include "console/telemetry/telemetry_model.h"
#include "robot/link/link_client.h"
#include "robot/link/link_pose.h"
#include "robot/record/recording_reader.h"
#include "tests/console/console_rig.h"

namespace telesphere::console {
namespace {

using namespace telesphere::console::test_rig;

// A plot's axis holds series of one unit, and the label names it: a supervisor reads a value off
// the axis (the scene-depth plot had tiles matched in % and the depth's age in ms on one axis).
TEST(SupervisorPlots, EachAxisCarriesOneUnitItsLabelNames) {
  std::set<std::string> plotted;
  for (const PlotSpec& spec : supervisorPlots()) {
    for (const bool right : {false, true}) {
      std::set<std::string> units;
      for (const PlotLine& line : spec.lines)
        if (line.right_axis == right) units.insert(telemetry::TelemetryModel::infoOf(line.series.c_str()).unit);
      const QString label = right ? spec.y2_label : spec.y_label;
      if (units.empty()) {
        EXPECT_TRUE(label.isEmpty()) << spec.title.toStdString() << ": an axis label without a line";
        continue;
      }
      ASSERT_EQ(units.size(), 1u) << spec.title.toStdString() << (right ? " right" : " left") << " axis mixes units";
      const std::string& unit = *units.begin();
      if (label.contains('[')) {
        EXPECT_TRUE(label.contains(QString::fromStdString("[" + unit + "]")))
            << spec.title.toStdString() << ": \"" << label.toStdString() << "\" does not name " << unit;
      }
    }
    for (const PlotLine& line : spec.lines) plotted.insert(line.series);
  }
  // Both cameras' depth confidence and the sweep's cost are on screen, not only the left camera's.
  for (const char* name : {telemetry::series::kDepthRadiusLeftM, telemetry::series::kDepthRadiusRightM,
                           telemetry::series::kDepthMatchedLeftPct, telemetry::series::kDepthMatchedRightPct,
                           telemetry::series::kDepthAgeMs, telemetry::series::kDepthSweepMs})
    EXPECT_TRUE(plotted.count(name)) << name << " is in no plot";
}

TEST(ConsoleWindow, WaitsForAnAbsentRobotWithoutFreezing) {
  Rig rig(27800);
  int polls = 0;
  QObject::connect(rig.session.get(), &ConsoleSession::updated, [&] { ++polls; });
  pumpFor(1500);
  EXPECT_GE(polls, 30);  // the poll ran every 20 ms: the window never blocked on the absent robot
  const QString expected = "waiting for robot at tcp://127.0.0.1:27803";
  EXPECT_TRUE(rig.window->connectionText().contains(expected)) << rig.window->connectionText().toStdString();
  EXPECT_TRUE(rig.window->healthPanel()->value("Robot", "link").startsWith(expected));
  EXPECT_FALSE(rig.window->controlPanel()->stopButton()->isEnabled());
  EXPECT_FALSE(rig.window->nominalPanel()->holdButton()->isEnabled());
  EXPECT_GT(rig.window->plots()[0]->lastRefreshMs(), 0.0);  // the empty plots still scroll
  saveShot(rig.window.get(), "console_waiting_for_robot.png");
  // The robot comes up later: the console picks it up by itself.
  rig.startRobot();
  ASSERT_TRUE(pumpUntil([&] { return rig.session->robot().state() == supervision::PeerState::kConnected; })) << rig.logs();
  EXPECT_TRUE(pumpUntil([&] { return rig.window->connectionText().contains("robot connected"); }))
      << rig.window->connectionText().toStdString();
}

TEST(ConsoleWindow, SupervisesTheRunningSystemAndEveryControlReachesRobotAndXrApp) {
  Rig rig(27810);
  rig.startRobot();
  rig.startXr(false);
  ASSERT_TRUE(pumpUntil([&] { return rig.connected(); }, 60000)) << rig.logs();
  // Let the robot take its first head poses as the nominal pose (the console's way is tested
  // below): the demo look-around then moves the robot head.
  {
    link::proto::ControlRequest r;
    r.set_capture_nominal(true);
    bool done = false;
    ASSERT_TRUE(pumpUntil([&] {
      if (!done) rig.session->request(r, "capture_nominal", [&](const ControlOutcome& o) { done = o.ok; });
      pumpFor(200);
      return done;
    }));
  }
  ASSERT_TRUE(pumpUntil([&] {
    return rig.samples(telemetry::series::kLatencyStages[5]) > 20 && rig.samples(telemetry::series::kHeadLatency) > 100 &&
           rig.samples(telemetry::series::kVOp) > 50 && rig.samples(telemetry::series::kVRob) > 50 && rig.samples(telemetry::series::kDeltaS) > 50 &&
           rig.samples(telemetry::series::kXrFrameMs) > 50;
  })) << rig.logs();

  // A calibration still through the link (issue #15's samples): both images at the cameras'
  // full 320×180, grey, with the head joints at the capture time between two joint states.
  {
    link::proto::ControlRequest r;
    r.set_calibration_capture(true);
    std::optional<ControlOutcome> outcome;
    rig.session->request(r, "calibration_capture", [&](const ControlOutcome& o) { outcome = o; });
    ASSERT_TRUE(pumpUntil([&] { return outcome.has_value(); }));
    ASSERT_TRUE(outcome->ok) << outcome->text().toStdString();
    const auto& still = outcome->reply.still();
    for (const auto* image : {&still.left(), &still.right()}) {
      EXPECT_EQ(image->width(), 320u);
      EXPECT_EQ(image->height(), 180u);
      ASSERT_EQ(image->gray8().size(), 320u * 180u);
      const auto [lo, hi] = std::minmax_element(image->gray8().begin(), image->gray8().end(),
                                                [](char a, char b) { return std::uint8_t(a) < std::uint8_t(b); });
      EXPECT_GT(std::uint8_t(*hi) - std::uint8_t(*lo), 100);  // the room, not a blank image
    }
    EXPECT_EQ(still.head_joints_size(), 6);
    EXPECT_LE(still.joints_before_ns(), still.capture_ns());
    EXPECT_GE(still.joints_after_ns(), still.capture_ns());
    EXPECT_LE(still.joints_after_ns() - still.joints_before_ns(), 20'000'000);  // 100 Hz states
  }

  // Source time: each image-latency sample sits at its capture time, so capture + latency is
  // when it was shown: in the past, or at most one display period (30 Hz here) ahead, since the
  // XR app stamps the display time it was promised. A sample stamped at its receive time would
  // lie a whole latency (≥ 40 ms here) later.
  const double now = rig.session->now();
  const telemetry::TimeSeries& shown = *rig.session->series().find(telemetry::series::kLatencyStages[5]);
  for (std::size_t i = 0; i < shown.size(); ++i) {
    EXPECT_LE(shown[i].t + shown[i].v * 1e-3, now + 1.0 / 30 + 0.005) << i;
    EXPECT_GT(shown[i].v, 0.0) << i;
  }
  // The robot's sample of a frame (capture → encoded) and the XR app's (capture → displayed)
  // arrive at different times by different routes, yet sit at the same capture time.
  const telemetry::TimeSeries& encoded = *rig.session->series().find(telemetry::series::kLatencyStages[0]);
  std::size_t matched = 0;
  for (std::size_t i = 0; i < shown.size(); ++i) {
    const auto [a, b] = encoded.indexRange(shown[i].t - 0.001, shown[i].t + 0.001);
    matched += b > a;
  }
  EXPECT_GE(matched, shown.size() * 8 / 10) << matched << " of " << shown.size();
  // Stages are cumulative: each band is non-negative.
  for (int stage = 1; stage < 6; ++stage) {
    const telemetry::TimeSeries& a = *rig.session->series().find(telemetry::series::kLatencyStages[stage - 1]);
    const telemetry::TimeSeries& b = *rig.session->series().find(telemetry::series::kLatencyStages[stage]);
    if (stage == 2) continue;  // robot and XR series sample different frames
    const std::size_t n = std::min(a.size(), b.size());
    for (std::size_t i = 0; i < n; ++i)
      if (a[a.size() - 1 - i].t == b[b.size() - 1 - i].t) {
        EXPECT_LE(a[a.size() - 1 - i].v, b[b.size() - 1 - i].v + 1e-9);
      }
  }
  const telemetry::TimeSeries& head = *rig.session->series().find(telemetry::series::kHeadLatency);
  EXPECT_GT(head.back().v, -1.0);
  EXPECT_LT(head.back().v, 200.0);
  EXPECT_EQ(rig.session->telemetry().counts().robot_batches_lost, 0u);

  // The preview stream shows both cameras.
  ASSERT_TRUE(pumpUntil([&] { return !rig.session->preview().left.isNull(); })) << rig.logs();
  EXPECT_EQ(rig.session->preview().left.width(), 320);  // the 320 px default preview of a 320 px camera
  pumpFor(400);
  EXPECT_TRUE(rig.window->previewPanel()->caption().contains("mode full 6D"))
      << rig.window->previewPanel()->caption().toStdString();

  // Screenshots: the main window on every plot (a 10 s window: the run is young), and each panel.
  for (LivePlot* plot : rig.window->plots()) plot->setWindowSeconds(10);
  for (int i = 0; i < rig.window->plotTabs()->count(); ++i) {
    auto* plot = qobject_cast<LivePlot*>(rig.window->plotTabs()->widget(i));
    if (!plot) continue;  // the Internet link's tab (its own test)
    rig.window->plotTabs()->setCurrentIndex(i);
    rig.window->redraw(true);
    pumpFor(100);
    saveShot(plot, QString("plot_%1.png").arg(i));
  }
  rig.window->plotTabs()->setCurrentIndex(0);
  rig.window->redraw(true);
  pumpFor(300);
  saveShot(rig.window.get(), "console_main.png");
  saveShot(rig.window->dockOf(rig.window->healthPanel()), "panel_health.png");
  saveShot(rig.window->dockOf(rig.window->previewPanel()), "panel_cameras.png");

  // Export: CSV of the visible data, PNG and PDF of the plot.
  LivePlot* latency = rig.window->plots()[0];
  QString error;
  const QString csv = rig.dir.filePath("latency.csv");
  ASSERT_TRUE(latency->exportCsv(csv, &error)) << error.toStdString();
  QFile csv_file(csv);
  ASSERT_TRUE(csv_file.open(QIODevice::ReadOnly));
  const QStringList rows = QString::fromUtf8(csv_file.readAll()).split('\n', Qt::SkipEmptyParts);
  EXPECT_EQ(rows[0], "series,label,unit,t_s,value");
  EXPECT_GT(rows.size(), 40);
  EXPECT_TRUE(rows.filter("latency.displayed,capture → displayed,ms,").size() > 10);
  ASSERT_TRUE(latency->exportPng(rig.dir.filePath("latency.png"), &error));
  ASSERT_TRUE(latency->exportPdf(rig.dir.filePath("latency.pdf"), &error));
  EXPECT_GT(QFile(rig.dir.filePath("latency.png")).size(), 5000);
  EXPECT_GT(QFile(rig.dir.filePath("latency.pdf")).size(), 5000);

  // Pause freezes the view while data keeps coming; resuming follows again.
  latency->setPaused(true);
  const auto frozen = latency->visibleRange();
  pumpFor(500);
  rig.window->redraw(true);
  EXPECT_EQ(latency->visibleRange(), frozen);
  latency->setPaused(false);
  EXPECT_GT(latency->visibleRange().second, frozen.second + 0.3);

  // Every control, through the panel's own editors and buttons; each reply is shown.
  ControlPanel* control = rig.window->controlPanel();
  const auto health = [&] { return rig.session->health() ? rig.session->health()->settings() : link::proto::RobotSettings{}; };
  const auto waitOk = [&](const QString& what) {
    EXPECT_TRUE(pumpUntil([&] { return control->lastOutcome().startsWith(what) && control->lastOutcome().endsWith(": ok"); }))
        << control->lastOutcome().toStdString();
  };
  control->modeBox()->setCurrentIndex(control->modeBox()->findData(int(link::proto::VISUAL_MODE_FIXED)));
  rig.click(control->applyButton("visual mode"));
  waitOk("set_visual_mode");
  EXPECT_TRUE(pumpUntil([&] {
    return health().visual_mode() == link::proto::VISUAL_MODE_FIXED &&
           rig.session->telemetry().xrVisualMode() == link::proto::VISUAL_MODE_FIXED;  // the XR app follows
  })) << rig.logs();
  control->radiusBox()->setValue(2.5);
  rig.click(control->applyButton("sphere radius"));
  waitOk("set_sphere_radius");
  EXPECT_TRUE(pumpUntil([&] {
    return health().sphere_radius() == 2.5 && rig.session->telemetry().xrSphereRadius() == 2.5;
  }));
  control->qualityBox()->setValue(60);
  rig.click(control->applyButton("JPEG quality"));
  waitOk("set_jpeg_quality");
  EXPECT_TRUE(pumpUntil([&] { return health().jpeg_quality() == 60; }));
  control->cutoffBox()->setValue(30);
  rig.click(control->applyButton("filter cut-off"));
  waitOk("set_filter_cutoff");
  EXPECT_TRUE(pumpUntil([&] { return health().filter_cutoff_hz() == 30; }));
  control->cutoffOffBox()->setChecked(true);
  rig.click(control->applyButton("filter cut-off"));
  EXPECT_TRUE(pumpUntil([&] { return std::isinf(health().filter_cutoff_hz()); }));
  control->jumpPositionBox()->setValue(5);
  control->jumpAngleBox()->setValue(12);
  rig.click(control->applyButton("jump threshold"));
  waitOk("set_jump_threshold");
  EXPECT_TRUE(pumpUntil([&] {
    return std::abs(health().jump_position_m() - 0.05) < 1e-9 && std::abs(health().jump_angle_deg() - 12) < 1e-9;
  }));
  // The scene proxy (#35): the robot holds the choice, the XR app follows it, measures the
  // stereo depth behind it and says so in its telemetry (plotted: each eye's radius, the tiles
  // matched, the depth's age).
  EXPECT_TRUE(control->proxyText().startsWith("none chosen")) << control->proxyText().toStdString();
  control->proxyBox()->setCurrentIndex(control->proxyBox()->findData(int(link::proto::DEPTH_PROXY_RADIUS)));
  rig.click(control->applyButton("scene proxy"));
  waitOk("set_depth_proxy");
  EXPECT_TRUE(pumpUntil([&] {
    return health().depth_proxy() == link::proto::DEPTH_PROXY_RADIUS &&
           rig.session->telemetry().xrDepthProxy() == link::proto::DEPTH_PROXY_RADIUS;
  })) << rig.logs();
  const auto depthSamples = [&](const char* name) { return rig.session->series().find(name)->size(); };
  EXPECT_TRUE(pumpUntil([&] { return depthSamples(telemetry::series::kDepthMatchedLeftPct) >= 5; }, 20000))
      << "no stereo depth from the XR app: " << rig.logs();
  EXPECT_TRUE(pumpUntil([&] {
    return control->proxyText() == "one radius from depth · XR app: one radius from depth";
  })) << control->proxyText().toStdString();
  {
    const telemetry::TimeSeries& radius = *rig.session->series().find(telemetry::series::kDepthRadiusLeftM);
    const telemetry::TimeSeries& matched = *rig.session->series().find(telemetry::series::kDepthMatchedLeftPct);
    const telemetry::TimeSeries& age = *rig.session->series().find(telemetry::series::kDepthAgeMs);
    ASSERT_FALSE(radius.empty());
    ASSERT_FALSE(age.empty());
    // The simulated room: its walls and table lie 0.5–5 m from the cameras.
    EXPECT_GT(radius.back().v, 0.3);
    EXPECT_LT(radius.back().v, 6.0);
    EXPECT_GT(matched.back().v, 0.0);
    EXPECT_LE(matched.back().v, 100.0);
    EXPECT_GT(age.back().v, 0.0);
    EXPECT_LT(age.back().v, 2000.0);
  }
  // A refusal comes back with the robot's words.
  {
    link::proto::ControlRequest r;
    r.set_set_sphere_radius(0.01);
    std::optional<ControlOutcome> outcome;
    rig.session->request(r, "set_sphere_radius 0.01 m", [&](const ControlOutcome& o) { outcome = o; });
    ASSERT_TRUE(pumpUntil([&] { return outcome.has_value(); }));
    EXPECT_TRUE(outcome->answered);
    EXPECT_FALSE(outcome->ok);
    EXPECT_TRUE(outcome->text().contains("refused: sphere radius")) << outcome->text().toStdString();
    EXPECT_EQ(outcome->reply.settings().sphere_radius(), 2.5);
  }
  // Recording: the button starts one in the robot's record folder, health shows it, again stops it.
  ASSERT_TRUE(pumpUntil([&] { return control->recordButton()->isEnabled(); })) << control->recordingText().toStdString();
  rig.click(control->recordButton());
  ASSERT_TRUE(pumpUntil([&] { return rig.session->health() && rig.session->health()->recording().active(); }));
  EXPECT_TRUE(pumpUntil([&] { return control->recordingText().startsWith("● session-"); }))
      << control->recordingText().toStdString();
  EXPECT_EQ(control->recordButton()->text(), "Stop recording");
  pumpFor(300);
  saveShot(rig.window->dockOf(control), "panel_control.png");
  for (int i = 0; i < rig.window->plotTabs()->count(); ++i) {
    const QString tab = rig.window->plotTabs()->tabText(i);
    if (tab != "Scene depth" && tab != "Scene depth timing") continue;
    rig.window->plotTabs()->setCurrentIndex(i);
    rig.window->redraw(true);
    pumpFor(100);
    saveShot(rig.window->plotTabs()->widget(i), tab == "Scene depth" ? "plot_scene_depth.png" : "plot_scene_depth_timing.png");
    rig.window->plotTabs()->setCurrentIndex(0);
  }
  rig.click(control->recordButton());
  ASSERT_TRUE(pumpUntil([&] { return rig.session->health() && !rig.session->health()->recording().active(); }));
  const std::string recorded = rig.session->health()->recording().file();
  EXPECT_TRUE(QFileInfo::exists(QString::fromStdString(recorded))) << recorded;
  EXPECT_GT(rig.session->health()->recording().messages(), 0u);
  {
    // The recording keeps the session's proxy (robot state) and what the XR app rendered with.
    std::string error;
    const auto reader = record::RecordingReader::open(recorded, &error);
    ASSERT_TRUE(reader) << error;
    std::size_t states_with_proxy = 0, batches_with_depth = 0;
    record::RecordedSessionVisitor visitor;
    visitor.message = [&](record::RecordedTopic topic, const record::McapMessageView& m) {
      if (topic == record::RecordedTopic::kRobotState) {
        link::proto::RobotState state;
        if (state.ParseFromArray(m.data, int(m.size)) && state.depth_proxy() == link::proto::DEPTH_PROXY_RADIUS)
          ++states_with_proxy;
      } else if (topic == record::RecordedTopic::kXrTelemetry) {
        link::proto::XrTelemetry t;
        if (t.ParseFromArray(m.data, int(m.size)) && t.depth().proxy() == link::proto::DEPTH_PROXY_RADIUS &&
            t.depth().radius_m_size() == 2 && t.depth().matched_fraction_size() == 2)
          ++batches_with_depth;
      }
      return true;
    };
    ASSERT_TRUE(reader->forEach(visitor, &error)) << error;
    EXPECT_GT(states_with_proxy, 0u);
    EXPECT_GT(batches_with_depth, 0u);
  }
  EXPECT_TRUE(pumpUntil([&] { return control->recordingText().startsWith("last: session-"); }))
      << control->recordingText().toStdString();

  // Arm stop: the fault banner stays until acknowledged, also after the fault is cleared.
  rig.click(control->stopButton());
  ASSERT_TRUE(pumpUntil([&] { return rig.window->faultBanner()->isVisible(); }));
  EXPECT_TRUE(rig.window->faultBanner()->text().contains("arm stopped from the console"));
  EXPECT_TRUE(pumpUntil([&] { return rig.window->healthPanel()->value("Arm and head", "arm").startsWith("FAULT"); }, 2000));
  saveShot(rig.window.get(), "console_fault.png");
  rig.click(control->clearFaultButton());
  ASSERT_TRUE(pumpUntil([&] { return rig.session->health() && rig.session->health()->arm_ok(); }));
  pumpFor(300);
  EXPECT_TRUE(rig.window->faultBanner()->isVisible());
  EXPECT_TRUE(rig.window->faultBanner()->text().contains("cleared"));
  rig.window->faultBanner()->acknowledgeButton()->click();
  pumpFor(100);
  EXPECT_FALSE(rig.window->faultBanner()->isVisible());
}

TEST(ConsoleWindow, TheInternetLinkTabShowsTheMediaPathAndTheCapReachesTheRobot) {
  Rig rig(28330);
  rig.startRobot();
  rig.startXr(false, {"--video-link", "udp"});
  ASSERT_TRUE(pumpUntil([&] { return rig.connected(); }, 60000)) << rig.logs();
  LinkPanel* panel = rig.window->linkPanel();
  rig.window->plotTabs()->setCurrentWidget(panel);
  for (LivePlot* plot : panel->plots()) plot->setWindowSeconds(20);
  // The XR app's receiver said hello: the robot names it, and the samples of every frame come.
  ASSERT_TRUE(pumpUntil([&] {
    const auto& h = rig.session->health();
    return h && h->has_media() && !h->media().receiver_address().empty() &&
           rig.samples(telemetry::series::kLinkTargetMbit) > 20 && rig.samples(telemetry::series::kLinkRttMs) > 5 &&
           rig.samples(telemetry::series::kLinkRepairedPerS) > 5;
  }, 30000)) << rig.logs();
  EXPECT_TRUE(panel->summaryText().contains("media path</b> to 127.0.0.1:")) << panel->summaryText().toStdString();
  EXPECT_EQ(panel->capText(), "now: none");
  const telemetry::TimeSeries& rtt = *rig.session->series().find(telemetry::series::kLinkRttMs);
  EXPECT_GE(rtt.back().v, 0.0);
  EXPECT_LT(rtt.back().v, 100.0) << "loopback";

  // The supervisor caps the path at 1 Mbit/s: the robot takes it, its target follows, the
  // stream gives up frame rate and scale, and the graphs mark the moment.
  panel->requestCap(1.0);
  ASSERT_TRUE(pumpUntil([&] {
    const auto& h = rig.session->health();
    return h && h->media().now().cap_mbit() == 1.0 && h->settings().media_cap_mbit() == 1.0;
  })) << rig.logs();
  ASSERT_TRUE(pumpUntil([&] { return panel->capText() == "now 1.0 Mbit/s"; })) << panel->capText().toStdString();
  ASSERT_TRUE(pumpUntil([&] {
    const telemetry::TimeSeries* target = rig.session->series().find(telemetry::series::kLinkTargetMbit);
    const telemetry::TimeSeries* scale = rig.session->series().find(telemetry::series::kLinkScalePct);
    return target->back().v <= 1.0 + 1e-9 && scale->back().v < 100.0;
  }, 15000)) << rig.logs();
  EXPECT_GT(rig.samples(telemetry::series::kLinkCapMbit), 0u);
  EXPECT_TRUE(panel->summaryText().contains("below nominal, limited by")) << panel->summaryText().toStdString();
  pumpFor(3000);
  rig.window->redraw(true);
  pumpFor(200);
  saveShot(panel, "panel_link.png");
  saveShot(rig.window.get(), "console_link.png");

  // Lifting it: none in force.
  panel->requestCap(0.0);
  ASSERT_TRUE(pumpUntil([&] { return panel->capText() == "now: none"; })) << panel->capText().toStdString();
}

TEST(ConsoleWindow, NominalPoseStepEndToEnd) {
  Rig rig(27820);
  rig.startRobot();
  rig.startXr(true);
  ASSERT_TRUE(pumpUntil([&] { return rig.connected(); }, 60000)) << rig.logs();
  NominalPosePanel* panel = rig.window->nominalPanel();
  rig.window->dockOf(panel)->raise();
  // Capture needs the hold step first; the button stays off until then.
  pumpFor(500);
  EXPECT_FALSE(panel->captureButton()->isEnabled());
  rig.click(panel->holdButton());
  ASSERT_TRUE(pumpUntil([&] {
    return rig.session->robotState() && rig.session->robotState()->nominal_step() == link::proto::NOMINAL_STEP_HOLDING;
  })) << panel->statusText().toStdString();
  ASSERT_TRUE(pumpUntil([&] { return panel->captureButton()->isEnabled(); })) << panel->gate().reason;
  ASSERT_TRUE(panel->gate().angles);
  EXPECT_NEAR(panel->gate().angles->yaw * 180 / M_PI, 20.0, 0.01);
  EXPECT_NEAR(panel->gate().angles->pitch * 180 / M_PI, -8.0, 0.01);
  rig.click(panel->captureButton());
  ASSERT_TRUE(pumpUntil([&] { return panel->confirmButton()->isEnabled(); })) << panel->statusText().toStdString();
  ASSERT_TRUE(panel->mapping());
  EXPECT_NEAR(panel->mapping()->yaw_deg(), 20.0, 0.01);
  EXPECT_NEAR(panel->mapping()->pitch_deg(), -8.0, 0.01);
  EXPECT_NEAR(panel->mapping()->roll_deg(), 0.0, 0.01);
  pumpFor(200);
  saveShot(rig.window->dockOf(panel), "panel_nominal_pose.png");
  rig.click(panel->confirmButton());
  ASSERT_TRUE(pumpUntil([&] {
    const auto& s = rig.session->robotState();
    return s && s->nominal_set() && s->nominal_step() == link::proto::NOMINAL_STEP_FOLLOWING;
  }));
  const auto first_mapping = rig.session->robotState()->t_robot_vr();

  // Once more, then undo back to the first.
  ASSERT_TRUE(pumpUntil([&] { return panel->holdButton()->isEnabled(); }));
  rig.click(panel->holdButton());
  ASSERT_TRUE(pumpUntil([&] { return panel->captureButton()->isEnabled(); }));
  rig.click(panel->captureButton());
  ASSERT_TRUE(pumpUntil([&] { return panel->confirmButton()->isEnabled(); }));
  rig.click(panel->confirmButton());
  ASSERT_TRUE(pumpUntil([&] { return panel->mapping() && panel->mapping()->has_previous() && panel->undoButton()->isEnabled(); }));
  rig.click(panel->undoButton());
  ASSERT_TRUE(pumpUntil([&] { return panel->statusText() == "nominal: undo: ok"; })) << panel->statusText().toStdString();
  ASSERT_TRUE(pumpUntil([&] {
    const auto& s = rig.session->robotState();
    return s && s->t_robot_vr().SerializeAsString() == first_mapping.SerializeAsString();
  }));

  // Without fresh head poses the console does not offer a capture and the robot refuses one.
  rig.click(panel->holdButton());
  rig.xr->kill();
  ASSERT_TRUE(pumpUntil([&] { return !panel->gate().fresh; }));
  EXPECT_FALSE(panel->captureButton()->isEnabled());
  EXPECT_NE(panel->gate().reason.find("stale"), std::string::npos) << panel->gate().reason;
  pumpFor(300);  // the robot's own bound (250 ms since the newest pose arrived) has passed too
  link::proto::ControlRequest r;
  r.set_nominal_step(link::proto::NOMINAL_REQUEST_CAPTURE);
  std::optional<ControlOutcome> outcome;
  rig.session->request(r, "nominal: capture", [&](const ControlOutcome& o) { outcome = o; });
  ASSERT_TRUE(pumpUntil([&] { return outcome.has_value(); }));
  EXPECT_FALSE(outcome->ok);
  EXPECT_TRUE(outcome->error.contains("no fresh head pose")) << outcome->error.toStdString();
}

TEST(ConsoleWindow, AHeadHoldShowsItsHolderAndReleaseHeadEndsIt) {
  Rig rig(28270);
  rig.startRobot();
  ASSERT_TRUE(pumpUntil([&] { return rig.session->robotState() && rig.session->robotState()->arm_ok(); }, 60000))
      << rig.logs();
  ControlPanel* control = rig.window->controlPanel();
  rig.window->dockOf(control)->raise();
  ASSERT_TRUE(pumpUntil([&] { return control->holdText().startsWith("not held"); })) << control->holdText().toStdString();
  EXPECT_FALSE(control->releaseHeadButton()->isEnabled());

  // A wizard of its own (its own link client, as a headless wizard would be) holds the head.
  link::LinkEndpoints endpoints;
  endpoints.base_port = rig.port;
  link::LinkClient wizard_link(endpoints, link::LinkClient::Options{.frames = false});
  calibration::CalibrationRobot wizard(wizard_link, "test wizard");
  const auto T_head = wizard.headPose(std::chrono::seconds(10));
  ASSERT_TRUE(T_head);
  std::string error;
  ASSERT_TRUE(wizard.holdHeadAt(*T_head, &error)) << error;
  ASSERT_TRUE(pumpUntil([&] { return control->holdText().startsWith("held by test wizard, pid "); }))
      << control->holdText().toStdString();
  // Its renewals keep it held past several leases.
  pumpFor(4500);
  EXPECT_TRUE(control->holdText().startsWith("held by test wizard")) << control->holdText().toStdString();
  EXPECT_TRUE(wizard.holdLost().empty()) << wizard.holdLost();
  saveShot(rig.window->dockOf(control), "panel_control_head_hold.png");

  // The supervisor ends it: the head is free, the panel says who ended it, the wizard learns it
  // at its next renewal and never takes the head again by itself.
  rig.click(control->releaseHeadButton());
  ASSERT_TRUE(pumpUntil([&] { return rig.session->robotState()->hold().lease() == 0; }));
  ASSERT_TRUE(pumpUntil([&] { return control->holdText().contains("released by the console (supervisor)"); }))
      << control->holdText().toStdString();
  ASSERT_TRUE(pumpUntil([&] { return !wizard.holdLost().empty(); }, 3000));
  EXPECT_FALSE(wizard.holdHeadAt(*T_head, &error));
  EXPECT_NE(error.find("no longer holds the head"), std::string::npos) << error;
  EXPECT_FALSE(rig.session->robotState()->calibration_hold());
}

TEST(ConsoleWindow, PicksUpARestartedRobotAndNoticesTheXrAppGoing) {
  Rig rig(27830);
  rig.startRobot();
  rig.startXr(false);
  ASSERT_TRUE(pumpUntil([&] { return rig.connected() && rig.samples(telemetry::series::kVRob) > 20; }, 60000)) << rig.logs();

  rig.xr->kill();
  ASSERT_TRUE(pumpUntil([&] { return rig.session->xr().state() == supervision::PeerState::kGone; }, 15000));
  EXPECT_TRUE(rig.window->faultBanner()->text().contains("XR app gone"));
  EXPECT_EQ(rig.session->robot().state(), supervision::PeerState::kConnected);

  rig.robot->kill();  // SIGKILL: no goodbye
  ASSERT_TRUE(pumpUntil([&] { return rig.session->robot().state() == supervision::PeerState::kSilent; }, 5000));
  ASSERT_TRUE(pumpUntil([&] { return rig.session->robot().state() == supervision::PeerState::kGone; }, 15000));
  EXPECT_TRUE(rig.window->faultBanner()->text().contains("robot at tcp://127.0.0.1:27833 gone"));
  EXPECT_TRUE(pumpUntil([&] { return rig.window->connectionText().contains("robot gone"); }, 2000));
  saveShot(rig.window.get(), "console_robot_gone.png");
  const double gone_at = rig.session->now();

  rig.startRobot();
  ASSERT_TRUE(pumpUntil([&] { return rig.session->robot().state() == supervision::PeerState::kConnected; })) << rig.logs();
  // The first pong of the new process tells it apart from the old one.
  EXPECT_TRUE(pumpUntil([&] { return rig.session->activity().robot_restarts == 1; }, 5000));
  ASSERT_TRUE(pumpUntil([&] { return rig.session->series().find(telemetry::series::kVRob)->back().t > gone_at + 0.5; }))
      << rig.logs();
  EXPECT_TRUE(rig.window->faultBanner()->text().contains("the robot restarted"));
  // The silence is a gap in the plot, not a line across it.
  const telemetry::TimeSeries& v_rob = *rig.session->series().find(telemetry::series::kVRob);
  std::vector<telemetry::Sample> drawn;
  telemetry::ColumnDecimator().decimate(v_rob, v_rob.front().t, v_rob.back().t, (v_rob.back().t - v_rob.front().t) / 400, drawn);
  EXPECT_TRUE(std::any_of(drawn.begin(), drawn.end(), [](const telemetry::Sample& s) { return std::isnan(s.v); }));
}

// Issue #15: a wizard's result applied live from the "Calibration in use" panel. Only the part the
// wizard measured replaces the robot's calibration; the robot stamps its frames with it (their
// left-to-right camera offset is the new T_cam_l_cam_r) and the XR app renders with it; Revert goes
// back. Nothing restarts.
TEST(ConsoleWindow, ACalibrationAppliedLiveReachesRobotAndXrAppAndReverts) {
  Rig rig(27840);
  rig.startRobot();
  rig.startXr(true);
  CalibrationInUsePanel* panel = rig.window->calibrationInUsePanel();
  rig.window->dockOf(panel)->raise();
  ASSERT_TRUE(pumpUntil([&] {
    return rig.connected() && panel->inUse().has_value() && rig.session->telemetry().xrCalibrationGeneration() == 1u;
  }, 60000)) << rig.logs();
  EXPECT_EQ(panel->inUse()->generation(), 1u);
  EXPECT_EQ(panel->inUse()->previous(), 0u);
  auto* apply = panel->findChild<QPushButton*>("calibration_apply");
  auto* revert = panel->findChild<QPushButton*>("calibration_revert");
  ASSERT_TRUE(apply && revert);
  EXPECT_FALSE(apply->isEnabled()) << "nothing to apply before a wizard's result";
  EXPECT_FALSE(revert->isEnabled()) << "nothing to revert to at start";
  const auto start = calib::parseCalibration(panel->inUse()->yaml(), "robot");
  ASSERT_TRUE(start) << start.error().describe();

  // An intrinsics-and-stereo result: baseline 3 mm wider, cam_l's focal length 2 % longer. Its
  // T_flange_cam_l (the wizard's start file, 5 cm off here) must not be applied.
  calib::SystemCalibration result = *start;
  result.T_cam_l_cam_r->translation() += result.T_cam_l_cam_r->translation().normalized() * 0.003;
  Eigen::VectorXd p = result.cameras[0].camera.params();
  p[0] *= 1.02;
  p[1] *= 1.02;
  result.cameras[0].camera = *calib::GenericCamera::create(result.cameras[0].camera.modelName(), p);
  result.T_flange_cam_l->translation().z() += 0.05;
  panel->setCandidate(result, calibration::MeasuredParts::kCameras, "intrinsics wizard (test)");
  ASSERT_TRUE(pumpUntil([&] { return apply->isEnabled(); }));
  const auto* changes = panel->findChild<QTableWidget*>("calibration_in_use_changes");
  ASSERT_NE(changes, nullptr);
  QStringList rows;
  for (int r = 0; r < changes->rowCount(); ++r)
    rows << changes->item(r, 0)->text() + " " + changes->item(r, 1)->text();
  EXPECT_TRUE(rows.contains("T_cam_l_cam_r translation 3.00 mm")) << rows.join("; ").toStdString();
  EXPECT_TRUE(rows.contains("T_flange_cam_l translation 0.00 mm")) << rows.join("; ").toStdString();
  pumpFor(500);
  saveShot(rig.window->dockOf(panel), "panel_calibration_in_use.png");

  QElapsedTimer since_click;
  rig.click(apply);
  since_click.start();
  qint64 robot_ms = -1, xr_ms = -1;
  ASSERT_TRUE(pumpUntil([&] {
    if (robot_ms < 0 && rig.session->robotState() && rig.session->robotState()->calibration_generation() == 2u)
      robot_ms = since_click.elapsed();
    if (xr_ms < 0 && rig.session->telemetry().xrCalibrationGeneration() == 2u) xr_ms = since_click.elapsed();
    return panel->inUse() && panel->inUse()->generation() == 2u && robot_ms >= 0 && xr_ms >= 0;
  }, 30000)) << rig.logs();
  // Heard at the console: robot state at 50 Hz, XR telemetry every 100 ms relayed by the robot.
  std::printf("apply → robot state names generation 2: %lld ms; → XR telemetry renders it: %lld ms\n",
              static_cast<long long>(robot_ms), static_cast<long long>(xr_ms));
  EXPECT_FALSE(apply->isEnabled()) << "the robot already uses this result";
  const auto applied = calib::parseCalibration(panel->inUse()->yaml(), "robot");
  ASSERT_TRUE(applied);
  EXPECT_TRUE(applied->T_flange_cam_l->isApprox(*start->T_flange_cam_l, 1e-12)) << "the hand-eye stays";
  EXPECT_TRUE(applied->T_cam_l_cam_r->isApprox(*result.T_cam_l_cam_r, 1e-12));
  EXPECT_TRUE(revert->isEnabled());

  // The robot's frames of generation 2: the right camera sits at the new T_cam_l_cam_r.
  const auto frameOffset = [&](std::uint64_t generation) -> std::optional<Eigen::Isometry3d> {
    link::LinkEndpoints endpoints;
    endpoints.base_port = rig.port;
    link::LinkClient client(endpoints);
    for (int i = 0; i < 100; ++i) {
      const auto f = client.waitForFrame(std::chrono::milliseconds(500));
      if (!f || f->frame.calibration_generation() != generation) continue;
      return link::fromLinkPose(f->frame.left().t_robot_cam()).inverse() * link::fromLinkPose(f->frame.right().t_robot_cam());
    }
    return std::nullopt;
  };
  const auto offset2 = frameOffset(2);
  ASSERT_TRUE(offset2.has_value()) << rig.logs();
  EXPECT_LT((offset2->translation() - result.T_cam_l_cam_r->translation()).norm(), 0.0005);
  EXPECT_GT((offset2->translation() - start->T_cam_l_cam_r->translation()).norm(), 0.0025);
  pumpFor(300);
  saveShot(rig.window->dockOf(panel), "panel_calibration_in_use_applied.png");

  rig.click(revert);
  ASSERT_TRUE(pumpUntil([&] {
    return panel->inUse() && panel->inUse()->generation() == 3u &&
           rig.session->telemetry().xrCalibrationGeneration() == 3u;
  }, 30000)) << rig.logs();
  const auto reverted = calib::parseCalibration(panel->inUse()->yaml(), "robot");
  ASSERT_TRUE(reverted);
  EXPECT_TRUE(reverted->T_cam_l_cam_r->isApprox(*start->T_cam_l_cam_r, 1e-12));
  EXPECT_EQ(reverted->cameras[0].camera.params(), start->cameras[0].camera.params());
  const auto offset3 = frameOffset(3);
  ASSERT_TRUE(offset3.has_value());
  EXPECT_LT((offset3->translation() - start->T_cam_l_cam_r->translation()).norm(), 0.0005);
  EXPECT_FALSE(revert->isEnabled()) << "back at the start: nothing earlier";
  EXPECT_NE(rig.robot->output().indexOf("calibration generation 3 in use"), -1) << rig.logs();
}

}  // namespace
}  // namespace telesphere::console
