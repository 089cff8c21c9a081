// SPDX-License-Identifier: MIT
/// @brief FaultBanner: the unacknowledged faults, in words.
#include "console/widgets/fault_banner.h"

#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>

#include "console/widgets/console_session.h"

namespace telesphere::console {

FaultBanner::FaultBanner(ConsoleSession& session, QWidget* parent) : QFrame(parent), session_(session) {
  setObjectName("faultBanner");
  setStyleSheet("#faultBanner { background: #b3261e; border-radius: 4px; } QLabel { color: white; }");
  auto* layout = new QHBoxLayout(this);
  label_ = new QLabel;
  label_->setWordWrap(true);
  label_->setTextFormat(Qt::RichText);
  layout->addWidget(label_, 1);
  acknowledge_ = new QPushButton("Acknowledge");
  acknowledge_->setToolTip("Take these faults off the banner (they stay in the fault history)");
  connect(acknowledge_, &QPushButton::clicked, this, [this] { session_.acknowledgeFaults(); });
  layout->addWidget(acknowledge_);
  connect(&session_, &ConsoleSession::faultsChanged, this, &FaultBanner::refresh);
  connect(&session_, &ConsoleSession::updated, this, [this] {
    if (isVisible()) refresh();  // the "cleared 12 s ago" texts age
  });
  refresh();
}

void FaultBanner::refresh() {
  const auto faults = session_.faults().unacknowledged();
  if (faults.empty()) {
    label_->clear();
    hide();
    return;
  }
  const std::int64_t now = link::linkNowNs();
  QStringList lines;
  for (const supervision::Fault& f : faults) {
    QString line = "⚠ " + QString::fromStdString(f.text).toHtmlEscaped();
    if (f.times > 1) line += QString(" (%1 times)").arg(f.times);
    line += f.cleared_ns == 0 ? QString(" — since %1 ago").arg(QString::fromStdString(supervision::formatDuration(double(now - f.first_ns) * 1e-9)))
                              : QString(" — cleared %1 ago").arg(QString::fromStdString(supervision::formatDuration(double(now - f.cleared_ns) * 1e-9)));
    lines << line;
  }
  label_->setText("<b>Faults to acknowledge</b><br>" + lines.join("<br>"));
  show();
}

QString FaultBanner::text() const { return label_->text(); }

}  // namespace telesphere::console
