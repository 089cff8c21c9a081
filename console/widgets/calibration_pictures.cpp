// SPDX-License-Identifier: MIT
/// @brief The Calibration panel's pictures (see calibration_pictures.h).
#include "console/widgets/calibration_pictures.h"

#include <QColor>
#include <QPainter>
#include <algorithm>
#include <array>

namespace telesphere::console {
namespace {


/// Two reduced images of a stereo pair side by side (a 4 px gap) with `sample`'s corners drawn
/// on them in `corner_colour`, and each camera's corner count when `counts`.
QImage stereoPicture(const std::array<calib::GrayImage, 2>& images, const calibration::StereoSample& sample,
                     const QColor& corner_colour, double corner_radius, bool counts) {
  const int w = std::max(images[0].width, 1), h = std::max(images[0].height, 1);
  QImage image(2 * w + 4, h, QImage::Format_RGB32);
  image.fill(Qt::black);
  QPainter p(&image);
  p.setRenderHint(QPainter::Antialiasing);
  for (int c = 0; c < 2; ++c) {
    const calib::GrayImage& t = images[std::size_t(c)];
    if (t.width <= 0) continue;
    const QImage gray(t.pixels.data(), t.width, t.height, t.width, QImage::Format_Grayscale8);
    const int x0 = c * (w + 4);
    p.drawImage(x0, 0, gray);
    const double scale = sample.width > 0 ? double(t.width) / sample.width : 1.0;
    p.setPen(Qt::NoPen);
    p.setBrush(corner_colour);
    for (const Eigen::Vector2d& px : sample.views[std::size_t(c)].corners_px)
      p.drawEllipse(QPointF(x0 + px.x() * scale, px.y() * scale), corner_radius, corner_radius);
    if (counts) {
      p.setPen(Qt::white);
      p.drawText(QPointF(x0 + 6, 16), QString("%1: %2 corners")
                                          .arg(c == 0 ? "cam_l" : "cam_r")
                                          .arg(sample.views[std::size_t(c)].corner_ids.size()));
    }
  }
  return image;
}

}  // namespace

/// A sample's two thumbnails with its corners (the sample list).
QImage sampleImage(const calibration::StereoSample& s) { return stereoPicture(s.thumbnails, s, QColor(255, 60, 60), 1.2, false); }

/// A live still: the corners green when the gates pass and orange when not.
QImage liveImage(const calibration::LiveStill& still) {
  return stereoPicture(still.view, still.sample, still.verdict.keep ? QColor(60, 220, 60) : QColor(255, 150, 0), 1.6, true);
}

/// The polar bins of both cameras as rows of cells: reached (green), required and missing (red),
/// optional (grey); the bin edges in degrees underneath.
QPixmap coveragePicture(const calibration::IntrinsicsCollector& collector, const calibration::IntrinsicsDoneRule& rule) {
  const int cell = 26, rows = 2, label_w = 52;
  const int bins = std::max(collector.coverage(0).polarBins(), collector.coverage(1).polarBins());
  QPixmap pixmap(label_w + bins * cell + 2, rows * (cell + 4) + 18);
  pixmap.fill(Qt::white);
  QPainter p(&pixmap);
  for (int c = 0; c < rows; ++c) {
    const calib::ViewCoverage& cov = collector.coverage(c);
    const std::vector<int> required = calibration::requiredPolarBins(cov, rule);
    p.setPen(Qt::black);
    p.drawText(QRect(0, c * (cell + 4), label_w, cell), Qt::AlignVCenter, c == 0 ? "cam_l" : "cam_r");
    for (int b = 0; b < cov.polarBins(); ++b) {
      const bool needed = std::find(required.begin(), required.end(), b) != required.end();
      const QColor fill = cov.polarCount(b) > 0 ? QColor(90, 180, 90) : needed ? QColor(220, 80, 80) : QColor(200, 200, 200);
      p.fillRect(QRect(label_w + b * cell, c * (cell + 4), cell - 2, cell), fill);
    }
  }
  p.setPen(Qt::black);
  for (int b = 0; b <= bins; b += 3) {
    p.drawText(QRect(label_w + b * cell - 12, rows * (cell + 4), 40, 16), Qt::AlignLeft,
               QString::number(b * collector.coverage(0).polarBinDeg()) + "°");
  }
  return pixmap;
}


}  // namespace telesphere::console
