// SPDX-License-Identifier: MIT
/// @brief What the console's widget tests share: a QApplication (offscreen), an event pump,
///        screenshots, telesphere processes on loopback, and a rig of robot, XR app, session and
///        main window. Header-only, for tests (each test file is its own binary).
#pragma once

#include <gtest/gtest.h>

#include <QApplication>
#include <QDir>
#include <QElapsedTimer>
#include <QFile>
#include <QProcess>
#include <QSettings>
#include <QPushButton>
#include <QTemporaryDir>
#include <QThread>
#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <memory>
#include <string>

#include "console/widgets/console_session.h"
#include "console/widgets/console_window.h"
#include "tests/console/event_pump.h"

namespace telesphere::console::test_rig {

class QtEnvironment : public ::testing::Environment {
 public:
  void SetUp() override {
    static int argc = 1;
    static char name[] = "console_window_test";
    static char* argv[] = {name, nullptr};
    app_ = std::make_unique<QApplication>(argc, argv);
    QApplication::setOrganizationName("telesphere-test");  // never the user's saved layout
    QApplication::setApplicationName("console_window_test");
    QSettings().clear();  // every run starts from the default layout (a test's raised dock is not kept)
  }
  void TearDown() override { app_.reset(); }

 private:
  std::unique_ptr<QApplication> app_;
};
inline const auto* const kQt = ::testing::AddGlobalTestEnvironment(new QtEnvironment);

inline QString screenshotDir() {
  const QByteArray env = qgetenv("TELESPHERE_SCREENSHOT_DIR");
  const QString dir = env.isEmpty() ? QString(TELESPHERE_BINARY_DIR "/console-screenshots") : QString(env);
  QDir().mkpath(dir);
  return dir;
}

inline void saveShot(QWidget* widget, const QString& name) {
  const QString path = screenshotDir() + "/" + name;
  EXPECT_TRUE(widget->grab().save(path, "PNG")) << path.toStdString();
}

/// A telesphere process on loopback, its output kept for a failure message.
class Process {
 public:
  /// `program` is a name in this tree's bin/, or an absolute path (a fixture from the demo tree).
  Process(const QString& program, const QStringList& args, const QString& log) : log_(log) {
    process_.setProcessChannelMode(QProcess::MergedChannels);
    process_.setStandardOutputFile(log);
    process_.start(program.startsWith('/') ? program : QString(TELESPHERE_BINARY_DIR "/bin/") + program, args);
    EXPECT_TRUE(process_.waitForStarted(10000)) << program.toStdString();
  }
  ~Process() { stop(); }
  void kill() {
    if (process_.state() == QProcess::NotRunning) return;
    process_.kill();
    process_.waitForFinished(10000);
  }
  void stop() {
    if (process_.state() == QProcess::NotRunning) return;
    process_.terminate();
    if (!process_.waitForFinished(10000)) kill();
  }
  QString output() const {
    QFile f(log_);
    return f.open(QIODevice::ReadOnly) ? QString::fromUtf8(f.readAll().right(3000)) : QString();
  }

 private:
  QProcess process_;
  QString log_;
};

struct Rig {
  QTemporaryDir dir;
  int port;
  std::unique_ptr<Process> robot, xr;
  std::unique_ptr<ConsoleSession> session;
  std::unique_ptr<ConsoleWindow> window;

  explicit Rig(int port_) : port(port_) {
    ConsoleSessionOptions options;
    options.endpoints.base_port = port;
    session = std::make_unique<ConsoleSession>(options);
    window = std::make_unique<ConsoleWindow>(*session);
    window->resize(1600, 950);
    window->show();
  }
  ~Rig() {
    window.reset();
    session.reset();
  }
  void startRobot() {
    robot = std::make_unique<Process>(
        "telesphere-robot",
        QStringList{"--insecure", "--sim", "--size", "320x180", "--fps", "15", "--port", QString::number(port), "--auto-nominal",
                    "false", "--stats-period", "0", "--preview-rate", "5", "--record-dir",
                    dir.filePath("recordings")},
        dir.filePath("robot.log"));
  }
  /// The XR app offscreen; `still`: the operator keeps the head still (a nominal pose), else the
  /// demo look-around.
  void startXr(bool still, const QStringList& extra = {}, const QString& eye_size = "96x96") {
    QStringList args{"offscreen", "--insecure", "--calib", TELESPHERE_SOURCE_DIR "/calib/data/sim_calibration.yaml", "--port",
                     QString::number(port), "--eye-size", eye_size, "--rate", "30", "--duration", "0", "--wait", "60"};
    if (still) {
      QFile csv(dir.filePath("still.csv"));
      EXPECT_TRUE(csv.open(QIODevice::WriteOnly));
      // Standing at 1.6 m, turned 20° left, looking 8° down, no roll (q = yaw · pitch).
      const Eigen::Quaterniond q = Eigen::AngleAxisd(20 * M_PI / 180, Eigen::Vector3d::UnitY()) *
                                   Eigen::AngleAxisd(-8 * M_PI / 180, Eigen::Vector3d::UnitX());
      csv.write(QString("t,px,py,pz,qx,qy,qz,qw\n0,0.1,1.6,0.2,%1,%2,%3,%4\n1,0.1,1.6,0.2,%1,%2,%3,%4\n")
                    .arg(q.x(), 0, 'g', 17)
                    .arg(q.y(), 0, 'g', 17)
                    .arg(q.z(), 0, 'g', 17)
                    .arg(q.w(), 0, 'g', 17)
                    .toUtf8());
      args << "--trajectory" << csv.fileName();
    }
    args << extra;
    xr = std::make_unique<Process>("telesphere-xr", args, dir.filePath("xr.log"));
  }
  std::string logs() const {
    return "--- robot\n" + (robot ? robot->output().toStdString() : "") + "\n--- xr\n" +
           (xr ? xr->output().toStdString() : "");
  }
  bool connected() const {
    return session->robot().state() == supervision::PeerState::kConnected && session->xr().state() == supervision::PeerState::kConnected;
  }
  std::size_t samples(const char* name) const {
    const telemetry::TimeSeries* s = session->series().find(name);
    return s ? s->size() : 0;
  }
  void click(QPushButton* button) {
    ASSERT_TRUE(button->isEnabled()) << button->text().toStdString();
    button->click();
  }
};

}  // namespace telesphere::console::test_rig
