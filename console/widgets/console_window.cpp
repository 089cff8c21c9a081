// SPDX-License-Identifier: MIT
/// @brief ConsoleWindow: layout, timers, persistence.
#include "console/widgets/console_window.h"

#include <QApplication>
#include <QCloseEvent>
#include <QDateTime>
#include <QDockWidget>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QSettings>
#include <QStatusBar>
#include <QTabWidget>
#include <QVBoxLayout>
#include <algorithm>

#include "console/widgets/camera_preview_panel.h"
#include "console/widgets/console_session.h"
#include "console/widgets/control_panel.h"
#include "console/widgets/fault_banner.h"
#include "console/widgets/health_panel.h"
#include "console/widgets/link_panel.h"
#include "console/widgets/live_plot.h"
#include "console/widgets/nominal_pose_panel.h"
#include "console/widgets/calibration_panel.h"
#include "console/widgets/calibration_in_use_panel.h"
#include "console/widgets/hand_eye_panel.h"
#include "console/widgets/study_panel.h"
#include "console/widgets/supervisor_plots.h"

namespace telesphere::console {

ConsoleWindow::ConsoleWindow(ConsoleSession& session, QWidget* parent) : QMainWindow(parent), session_(session) {
  setWindowTitle("telesphere console — robot at " + session_.endpoint());
  setObjectName("telesphereConsole");
  auto* central = new QWidget;
  auto* layout = new QVBoxLayout(central);
  layout->setContentsMargins(4, 4, 4, 4);
  banner_ = new FaultBanner(session_);
  layout->addWidget(banner_);
  connection_ = new QLabel;
  connection_->setObjectName("connectionLine");
  connection_->setTextFormat(Qt::RichText);
  layout->addWidget(connection_);
  tabs_ = new QTabWidget;
  QSettings settings;
  const double window_s = settings.value("plots/window_s", 30.0).toDouble();
  for (PlotSpec& spec : supervisorPlots()) {
    const QString title = spec.title;
    auto* plot = new LivePlot(session_.series(), [this] { return session_.now(); }, std::move(spec));
    plot->setWindowSeconds(window_s);
    connect(plot, &LivePlot::pausedChanged, this, [this] { updateDataHold(); });
    plots_.push_back(plot);
    tabs_->addTab(plot, title);
  }
  // The Internet link: its figures, the cap and its four graphs on one tab.
  link_ = new LinkPanel(session_, window_s);
  for (LivePlot* plot : link_->plots()) {
    connect(plot, &LivePlot::pausedChanged, this, [this] { updateDataHold(); });
    plots_.push_back(plot);
  }
  tabs_->addTab(link_, "Internet link");
  connect(tabs_, &QTabWidget::currentChanged, this, [this] { redraw(true); });
  // What the supervisor changed shows in the graphs where it took effect.
  connect(&session_, &ConsoleSession::controlAccepted, this, [this](double t, const QString& what) {
    for (LivePlot* plot : plots_) plot->addMarker(t, what);
  });
  layout->addWidget(tabs_, 1);
  setCentralWidget(central);

  const auto dock = [&](const QString& title, QWidget* panel, Qt::DockWidgetArea area) {
    auto* d = new QDockWidget(title, this);
    d->setObjectName("dock_" + title);
    d->setWidget(panel);
    addDockWidget(area, d);
    docks_.push_back(d);
    return d;
  };
  health_ = new HealthPanel(session_);
  preview_ = new CameraPreviewPanel(session_);
  control_ = new ControlPanel(session_);
  nominal_ = new NominalPosePanel(session_);
  study_ = new StudyPanel(session_);
  calibration_ = new CalibrationPanel(session_.options().endpoints);
  hand_eye_ = new HandEyePanel(session_.options().endpoints);
  in_use_ = new CalibrationInUsePanel(session_);
  // A wizard's result that meets its rule becomes the candidate to apply live.
  const auto offer = [this](const auto& outcome, calibration::MeasuredParts parts, const QString& what,
                             const QString& unit) {
    if (!outcome || !outcome->done || !outcome->calibration) return;
    const int count = outcome->collector ? int(outcome->collector->samples().size()) : 0;
    in_use_->setCandidate(*outcome->calibration, parts,
                          QString("%1, %2 %3, %4")
                              .arg(what)
                              .arg(count)
                              .arg(unit, QDateTime::currentDateTime().toString("HH:mm:ss")));
  };
  connect(calibration_, &CalibrationPanel::runFinished, this, [this, offer] {
    offer(calibration_->outcome(), calibration::MeasuredParts::kCameras, "intrinsics wizard", "views");
  });
  connect(hand_eye_, &HandEyePanel::runFinished, this, [this, offer] {
    offer(hand_eye_->outcome(), calibration::MeasuredParts::kHandEye, "hand-eye wizard", "samples");
  });
  QDockWidget* health_dock = dock("Health", health_, Qt::LeftDockWidgetArea);
  QDockWidget* cameras_dock = dock("Cameras", preview_, Qt::RightDockWidgetArea);
  QDockWidget* control_dock = dock("Control", control_, Qt::RightDockWidgetArea);
  QDockWidget* nominal_dock = dock("Nominal pose", nominal_, Qt::RightDockWidgetArea);
  QDockWidget* study_dock = dock("Study", study_, Qt::RightDockWidgetArea);
  QDockWidget* calibration_dock = dock("Calibration", calibration_, Qt::RightDockWidgetArea);
  QDockWidget* hand_eye_dock = dock("Hand-eye", hand_eye_, Qt::RightDockWidgetArea);
  QDockWidget* in_use_dock = dock("Calibration in use", in_use_, Qt::RightDockWidgetArea);
  tabifyDockWidget(control_dock, nominal_dock);
  tabifyDockWidget(control_dock, study_dock);
  tabifyDockWidget(control_dock, calibration_dock);
  tabifyDockWidget(control_dock, hand_eye_dock);
  tabifyDockWidget(control_dock, in_use_dock);
  control_dock->raise();

  QMenu* file = menuBar()->addMenu("&File");
  file->addAction("&Quit", QKeySequence::Quit, this, &QWidget::close);
  QMenu* view = menuBar()->addMenu("&View");
  for (QDockWidget* d : docks_) view->addAction(d->toggleViewAction());
  QMenu* help = menuBar()->addMenu("&Help");
  help->addAction("&About", this, [this] {
    QMessageBox::about(this, "telesphere console",
                       "telesphere console: the supervisor's view of the robot and the XR app.\n\n"
                       "The plots use QCustomPlot (GPL-3); this program, linked with it, is "
                       "distributed under the GPL-3.");
  });

  resize(1600, 950);
  resizeDocks({health_dock, cameras_dock}, {470, 440}, Qt::Horizontal);
  resizeDocks({cameras_dock, control_dock}, {300, 500}, Qt::Vertical);
  restoreGeometry(settings.value("window/geometry").toByteArray());
  restoreState(settings.value("window/state").toByteArray());

  redraw_timer_.setInterval(kRedrawIntervalMs);
  connect(&redraw_timer_, &QTimer::timeout, this, [this] { redraw(); });
  redraw_timer_.start();
  panel_timer_.setInterval(250);
  connect(&panel_timer_, &QTimer::timeout, this, &ConsoleWindow::refreshPanels);
  panel_timer_.start();
  refreshPanels();
}

ConsoleWindow::~ConsoleWindow() = default;

QDockWidget* ConsoleWindow::dockOf(QWidget* panel) const {
  for (QDockWidget* d : docks_)
    if (d->widget() == panel) return d;
  return nullptr;
}

QString ConsoleWindow::connectionText() const { return connection_->text(); }

std::vector<LivePlot*> ConsoleWindow::visiblePlots() const {
  if (auto* plot = qobject_cast<LivePlot*>(tabs_->currentWidget())) return {plot};
  if (tabs_->currentWidget() == link_) return link_->plots();
  return {};
}

void ConsoleWindow::redraw(bool force) {
  const std::vector<LivePlot*> visible = visiblePlots();
  if (visible.empty()) return;
  const qint64 now_ms = QDateTime::currentMSecsSinceEpoch();
  // New data, or the live time axis has moved a visible step (a silent link scrolls into a gap).
  const bool live = std::any_of(visible.begin(), visible.end(), [](const LivePlot* p) { return !p->paused(); });
  const bool changed = session_.series().version() != drawn_version_ || (live && now_ms - drawn_at_ms_ >= 100);
  if (!force && !changed) return;
  for (LivePlot* plot : visible) plot->refresh();
  drawn_version_ = session_.series().version();
  drawn_at_ms_ = now_ms;
}

void ConsoleWindow::refreshPanels() {
  health_->refresh();
  link_->refresh();
  preview_->refresh();
  in_use_->refresh();
  const supervision::PeerMonitor& robot = session_.robot();
  QString line;
  switch (robot.state()) {
    case supervision::PeerState::kWaiting:
      line = "<b style='color:#b3261e'>waiting for robot at " + session_.endpoint() + "</b> (" +
             QString::fromStdString(supervision::formatDuration(robot.seconds())) + ", retrying)";
      break;
    case supervision::PeerState::kConnected:
      line = "<b style='color:#1b5e20'>robot connected</b> for " + QString::fromStdString(supervision::formatDuration(robot.seconds()));
      break;
    default:
      line = "<b style='color:#b3261e'>robot " + QString(peerStateName(robot.state())) + "</b> for " +
             QString::fromStdString(supervision::formatDuration(robot.seconds())) + " at " + session_.endpoint() + " (retrying)";
  }
  if (const auto clock = session_.clock())
    line += QString(" · clock offset %1 ms, round trip %2 ms")
                .arg(double(clock->server_to_client_offset_ns) * 1e-6, 0, 'f', 3)
                .arg(double(clock->round_trip_ns) * 1e-6, 0, 'f', 3);
  const supervision::PeerMonitor& xr = session_.xr();
  line += " · XR app: " + (xr.state() == supervision::PeerState::kWaiting ? QString("not heard yet")
                                                              : QString::fromStdString(xr.describe()));
  // Trust (DESIGN.md §10): an open link, a refused key, refused peers are never out of sight.
  const bool insecure = !session_.options().endpoints.credentials.secure() ||
                        (session_.health() && session_.health()->trust().insecure());
  if (insecure) line = "<b style='color:#ffffff;background-color:#b3261e'>&nbsp;INSECURE LINK&nbsp;</b> · " + line;
  if (!session_.activity().refused_reason.empty())
    line += " · <b style='color:#b3261e'>" + QString::fromStdString(session_.activity().refused_reason).toHtmlEscaped() +
            "</b>";
  if (session_.health() && session_.health()->trust().refused_total() > 0)
    line += QString(" · <b style='color:#b3261e'>%1 refused</b> (Health → Trust)")
                .arg(session_.health()->trust().refused_total());
  connection_->setText(line);
  double redraw_ms = 0;
  for (const LivePlot* plot : visiblePlots()) redraw_ms += plot->lastRefreshMs();
  statusBar()->showMessage(QString("%1 samples in memory (%2 MB), last redraw %3 ms")
                               .arg(session_.series().totalSamples())
                               .arg(double(session_.series().bytes()) / 1e6, 0, 'f', 2)
                               .arg(redraw_ms, 0, 'f', 2));
}

void ConsoleWindow::updateDataHold() {
  std::optional<double> hold;
  for (LivePlot* p : plots_)
    if (p->paused()) hold = std::min(hold.value_or(p->visibleRange().first), p->visibleRange().first);
  session_.holdDataFrom(hold);
}

void ConsoleWindow::closeEvent(QCloseEvent* event) {
  // Everything entered is stored already; a trial still running ends as interrupted.
  study_->shutdown("the console window was closed during the trial");
  QSettings settings;
  settings.setValue("window/geometry", saveGeometry());
  settings.setValue("window/state", saveState());
  if (!plots_.empty()) settings.setValue("plots/window_s", plots_.front()->windowSeconds());
  event->accept();
}

}  // namespace telesphere::console
