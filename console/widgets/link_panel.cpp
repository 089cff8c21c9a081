// SPDX-License-Identifier: MIT
/// @brief LinkPanel: figures, cap, graphs.
#include "console/widgets/link_panel.h"

#include <QDoubleSpinBox>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>
#include <QVBoxLayout>

#include "console/widgets/console_session.h"
#include "console/widgets/link_plots.h"
#include "console/widgets/live_plot.h"

namespace telesphere::console {
namespace {

QString counts(const google::protobuf::RepeatedPtrField<link::proto::Count>& list) {
  QStringList parts;
  for (const auto& c : list) parts << QString("%1 %2").arg(QString::fromStdString(c.name())).arg(c.count());
  return parts.isEmpty() ? QString("none yet") : parts.join(", ");
}

}  // namespace

LinkPanel::LinkPanel(ConsoleSession& session, double window_s, QWidget* parent) : QWidget(parent), session_(session) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(2, 2, 2, 2);
  auto* top = new QHBoxLayout;
  summary_ = new QLabel;
  summary_->setObjectName("linkSummary");
  summary_->setTextFormat(Qt::RichText);
  summary_->setWordWrap(true);
  top->addWidget(summary_, 1);

  auto* cap_box = new QWidget;
  auto* cap_row = new QHBoxLayout(cap_box);
  cap_row->setContentsMargins(0, 0, 0, 0);
  cap_row->addWidget(new QLabel("cap"));
  cap_ = new QDoubleSpinBox;
  cap_->setRange(0.5, 10000.0);
  cap_->setDecimals(1);
  cap_->setValue(20.0);
  cap_->setSuffix(" Mbit/s");
  cap_->setToolTip("The most the media path may send (video, headers and repair), whatever the link would take: "
                   "for a shared uplink or a metered connection");
  cap_row->addWidget(cap_);
  set_cap_ = new QPushButton("Set cap");
  connect(set_cap_, &QPushButton::clicked, this, [this] { requestCap(cap_->value()); });
  cap_row->addWidget(set_cap_);
  lift_cap_ = new QPushButton("Lift cap");
  connect(lift_cap_, &QPushButton::clicked, this, [this] { requestCap(0.0); });
  cap_row->addWidget(lift_cap_);
  cap_now_ = new QLabel("–");
  cap_now_->setObjectName("linkCapNow");
  cap_row->addWidget(cap_now_);
  top->addWidget(cap_box, 0, Qt::AlignTop);
  layout->addLayout(top);

  decisions_ = new QLabel;
  decisions_->setWordWrap(true);
  decisions_->setStyleSheet("color: #555");
  layout->addWidget(decisions_);
  reply_ = new QLabel;
  layout->addWidget(reply_);

  auto* grid = new QGridLayout;
  grid->setSpacing(2);
  int i = 0;
  for (PlotSpec& spec : linkPlots()) {
    auto* plot = new LivePlot(session_.series(), [this] { return session_.now(); }, std::move(spec));
    plot->setWindowSeconds(window_s);
    plots_.push_back(plot);
    grid->addWidget(plot, i / 2, i % 2);
    ++i;
  }
  layout->addLayout(grid, 1);
  refresh();
}

void LinkPanel::requestCap(double cap_mbit) {
  link::proto::ControlRequest r;
  r.set_set_media_cap_mbit(cap_mbit);
  const QString what = cap_mbit > 0 ? QString("set_media_cap %1 Mbit/s").arg(cap_mbit) : QString("lift_media_cap");
  session_.request(std::move(r), what, [this](const ControlOutcome& outcome) {
    reply_->setText(outcome.text());
    reply_->setStyleSheet(outcome.ok ? "color: #1b5e20" : "color: #b3261e");
  });
}

QString LinkPanel::summaryText() const { return summary_->text(); }
QString LinkPanel::capText() const { return cap_now_->text(); }

void LinkPanel::refresh() {
  const bool connected = session_.robot().state() == supervision::PeerState::kConnected;
  const auto& health = session_.health();
  const bool media = health && health->has_media();
  set_cap_->setEnabled(connected && media);
  lift_cap_->setEnabled(connected && media);
  if (!health) {
    summary_->setText("<b>media path</b>: no word from the robot yet");
    decisions_->clear();
    cap_now_->setText("–");
    return;
  }
  if (!media) {
    summary_->setText("<b>media path</b>: this robot serves none (started with --no-media); video goes over the "
                      "ZeroMQ link only");
    decisions_->clear();
    cap_now_->setText("–");
    return;
  }
  const link::proto::MediaLinkHealth& m = health->media();
  const link::proto::MediaLinkSample& s = m.now();
  cap_now_->setText(s.cap_mbit() > 0 ? QString("now %1 Mbit/s").arg(s.cap_mbit(), 0, 'f', 1) : QString("now: none"));
  QString text;
  if (m.receiver_address().empty()) {
    text = QString("<b>media path</b> on UDP port %1: <b style='color:#b3261e'>no receiver</b> (no XR app has "
                   "said hello)").arg(m.port());
  } else {
    text = QString("<b>media path</b> to %1: delivered <b>%2</b> Mbit/s of target %3")
               .arg(QString::fromStdString(m.receiver_address()))
               .arg(s.delivered_mbit(), 0, 'f', 1)
               .arg(s.target_mbit(), 0, 'f', 1);
    text += s.rtt_ms() >= 0 ? QString("<br>round trip %1 ms").arg(s.rtt_ms(), 0, 'f', 0) : QString("<br>round trip –");
    const bool lossy = s.loss_fraction() > 0.05;
    text += QString(" · loss %1%2 %%3").arg(lossy ? "<b style='color:#b3261e'>" : "")
                .arg(s.loss_fraction() * 100.0, 0, 'f', 1).arg(lossy ? "</b>" : "");
    text += QString(" · queue %1 ms").arg(s.queue_delay_ms(), 0, 'f', 0);
  }
  if (const auto& xr = session_.xrStats())
    text += QString("%1frame age p50 %2 ms, p99 %3 ms").arg(QString(m.receiver_address().empty() ? "<br>" : " · ")).arg(xr->image_age_p50_ms(), 0, 'f', 0)
                .arg(xr->image_age_p99_ms(), 0, 'f', 0);
  const bool limited = s.limited_by() != "nothing" && !s.limited_by().empty();
  text += QString("<br>stream %1 Hz, scale %2 %, quality %3").arg(s.fps(), 0, 'f', 1)
              .arg(s.scale() * 100.0, 0, 'f', 0).arg(s.quality());
  if (limited)
    text += QString(" — <b style='color:#a15c00'>below nominal, limited by %1</b>").arg(QString::fromStdString(s.limited_by()));
  text += QString(" · framing overhead %1 %").arg(m.framing_overhead() * 100.0, 0, 'f', 1);
  // Sealed (DESIGN.md §10): what the session key refused is a peer without it, or a replay.
  if (m.sealed())
    text += QString("<br>sealed (AEAD, %1 session keys handed out) · %2%3 datagrams refused%4")
                .arg(m.seal_sessions())
                .arg(m.datagrams_unauthenticated() > 0 ? "<b style='color:#b3261e'>" : "")
                .arg(m.datagrams_unauthenticated())
                .arg(m.datagrams_unauthenticated() > 0 ? "</b>" : "");
  else
    text += "<br><b style='color:#b3261e'>not sealed (--insecure): anyone on the path can read and forge it</b>";
  summary_->setText(text);
  decisions_->setText(QString("rate decisions: %1<br>stream decisions (what limited it): %2<br>%3 frames sent, %4 "
                              "superseded before they left, %5 head target datagrams")
                          .arg(counts(m.rate_decisions()), counts(m.stream_decisions()))
                          .arg(m.frames_sent())
                          .arg(m.frames_superseded())
                          .arg(m.head_target_datagrams()));
}

}  // namespace telesphere::console
