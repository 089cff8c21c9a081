// SPDX-License-Identifier: MIT
/// @brief CameraPreviewPanel: two scaled pictures and a caption.
#include "console/widgets/camera_preview_panel.h"

#include <QGridLayout>
#include <QLabel>
#include <QPixmap>

#include "console/widgets/console_session.h"
#include "console/widgets/link_labels.h"

namespace telesphere::console {
namespace {

QLabel* imageLabel() {
  auto* label = new QLabel("no preview yet");
  label->setAlignment(Qt::AlignCenter);
  label->setMinimumSize(160, 90);
  label->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Ignored);
  label->setStyleSheet("background: #202020; color: #c0c0c0;");
  return label;
}

}  // namespace

CameraPreviewPanel::CameraPreviewPanel(ConsoleSession& session, QWidget* parent)
    : QWidget(parent), session_(session) {
  auto* layout = new QGridLayout(this);
  layout->setContentsMargins(2, 2, 2, 2);
  layout->addWidget(new QLabel("left camera"), 0, 0);
  layout->addWidget(new QLabel("right camera"), 0, 1);
  left_ = imageLabel();
  right_ = imageLabel();
  layout->addWidget(left_, 1, 0);
  layout->addWidget(right_, 1, 1);
  layout->setRowStretch(1, 1);
  caption_ = new QLabel;
  caption_->setWordWrap(true);
  layout->addWidget(caption_, 2, 0, 1, 2);
  connect(&session_, &ConsoleSession::previewChanged, this, &CameraPreviewPanel::showImages);
  refresh();
}

void CameraPreviewPanel::showImages() {
  const CameraPreview& p = session_.preview();
  for (auto [label, image] : {std::pair{left_, &p.left}, std::pair{right_, &p.right}})
    if (!image->isNull())
      label->setPixmap(QPixmap::fromImage(*image).scaled(label->size(), Qt::KeepAspectRatio, Qt::SmoothTransformation));
  refresh();
}

void CameraPreviewPanel::refresh() {
  const CameraPreview& p = session_.preview();
  QString text;
  if (p.left.isNull()) {
    text = "waiting for the robot's preview stream";
  } else {
    text = QString("frame %1, %2×%3 preview of %4×%5, captured %6 s ago")
               .arg(p.sequence)
               .arg(p.left.width())
               .arg(p.left.height())
               .arg(p.source_width)
               .arg(p.source_height)
               .arg(QString::number(session_.now() - p.capture_s, 'f', 2));
  }
  if (const auto& h = session_.health()) {
    const auto& st = h->settings();
    text += QString(" · mode %1 · sphere radius %2 m").arg(visualModeLabel(st.visual_mode())).arg(st.sphere_radius());
  }
  caption_->setText(text);
}

QString CameraPreviewPanel::caption() const { return caption_->text(); }

}  // namespace telesphere::console
