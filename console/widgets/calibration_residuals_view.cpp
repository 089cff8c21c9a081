// SPDX-License-Identifier: MIT
/// @brief CalibrationResidualsView (see calibration_residuals_view.h).
#include "console/widgets/calibration_residuals_view.h"

#include <qcustomplot.h>

#include <QHBoxLayout>
#include <QLabel>
#include <QPainter>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

#include "calib/view_coverage.h"

namespace telesphere::console {
namespace {

const QColor kCameraColour[2] = {QColor(31, 119, 180), QColor(230, 120, 20)};
constexpr double kBinDeg = 10.0;

/// `sample`'s thumbnail of camera `c`, enlarged to `width`, with every corner's error of that
/// view drawn from the observed corner, magnified.
QPixmap viewWithErrors(const calibration::StereoSample& sample, int c, const calib::CameraIntrinsicResult& cam,
                       int view, int width) {
  const calib::GrayImage& t = sample.thumbnails[std::size_t(c)];
  if (t.width <= 0 || sample.width <= 0) return {};
  const QImage gray(t.pixels.data(), t.width, t.height, t.width, QImage::Format_Grayscale8);
  QImage image = gray.convertToFormat(QImage::Format_RGB32).scaledToWidth(width, Qt::SmoothTransformation);
  const double scale = double(image.width()) / sample.width;
  QPainter p(&image);
  p.setRenderHint(QPainter::Antialiasing);
  p.setPen(QPen(QColor(255, 40, 40), 1.5));
  for (const calib::CornerResidual& r : cam.residuals) {
    if (r.view != view) continue;
    const QPointF from(r.px.x() * scale, r.px.y() * scale);
    const Eigen::Vector2d to = r.px + CalibrationResidualsView::kErrorMagnification * r.error_px;
    p.drawLine(from, QPointF(to.x() * scale, to.y() * scale));
  }
  return QPixmap::fromImage(image);
}

}  // namespace

CalibrationResidualsView::CalibrationResidualsView(QWidget* parent) : QWidget(parent) {
  auto* layout = new QVBoxLayout(this);
  plot_ = new QCustomPlot;
  plot_->setObjectName("calibration_residual_plot");
  plot_->setMinimumHeight(220);
  plot_->xAxis->setLabel("polar angle of the corner (°)");
  plot_->yAxis->setLabel("reprojection error (px)");
  plot_->legend->setVisible(true);
  plot_->legend->setFont(QFont(font().family(), 8));
  plot_->legend->setBrush(QColor(255, 255, 255, 210));
  layout->addWidget(plot_, 1);
  worst_title_ = new QLabel;
  worst_title_->setWordWrap(true);
  layout->addWidget(worst_title_);
  worst_row_ = new QHBoxLayout;
  layout->addLayout(worst_row_);
  clear();
}

void CalibrationResidualsView::clear() {
  plot_->clearGraphs();
  plot_->replot();
  worst_title_->setText("No result yet.");
  while (QLayoutItem* item = worst_row_->takeAt(0)) {
    delete item->widget();
    delete item;
  }
  worst_.clear();
}

void CalibrationResidualsView::showResult(const calib::IntrinsicResult& result,
                                          const calibration::IntrinsicsCollector* collector) {
  clear();
  double max_deg = kBinDeg, max_err = 0.5;
  for (std::size_t c = 0; c < result.cameras.size() && c < 2; ++c) {
    const calib::CameraIntrinsicResult& cam = result.cameras[c];
    QVector<double> x, y;
    std::vector<double> bin_sq, bin_n;
    for (const calib::CornerResidual& r : cam.residuals) {
      const double deg = calib::polarAngleDeg(cam.calibration.camera, r.px);
      if (!std::isfinite(deg)) continue;
      const double e = r.error_px.norm();
      x.push_back(deg);
      y.push_back(e);
      const auto b = std::size_t(deg / kBinDeg);
      if (b >= bin_sq.size()) bin_sq.resize(b + 1, 0.0), bin_n.resize(b + 1, 0.0);
      bin_sq[b] += e * e;
      bin_n[b] += 1;
      max_deg = std::max(max_deg, deg);
      max_err = std::max(max_err, e);
    }
    const QString label = QString::fromStdString(cam.calibration.label);
    QCPGraph* points = plot_->addGraph();
    points->setName(QString("%1 corners (%2)").arg(label).arg(x.size()));
    points->setLineStyle(QCPGraph::lsNone);
    QColor faint = kCameraColour[c];
    faint.setAlpha(90);
    points->setScatterStyle(QCPScatterStyle(QCPScatterStyle::ssDisc, faint, faint, 3));
    points->setData(x, y, true);
    QVector<double> bx, by;
    for (std::size_t b = 0; b < bin_sq.size(); ++b) {
      if (bin_n[b] == 0) continue;
      bx.push_back((double(b) + 0.5) * kBinDeg);
      by.push_back(std::sqrt(bin_sq[b] / bin_n[b]));
    }
    QCPGraph* rms = plot_->addGraph();
    rms->setName(QString("%1 RMS per %2° bin").arg(label).arg(kBinDeg, 0, 'f', 0));
    rms->setPen(QPen(kCameraColour[c], 2));
    rms->setScatterStyle(QCPScatterStyle(QCPScatterStyle::ssSquare, kCameraColour[c], kCameraColour[c], 5));
    rms->setData(bx, by, true);
  }
  plot_->xAxis->setRange(0, std::ceil(max_deg / kBinDeg) * kBinDeg);
  plot_->yAxis->setRange(0, max_err * 1.05);
  plot_->replot();

  struct Worst {
    int camera, view;
    double rms_px;
  };
  std::vector<Worst> worst;
  for (std::size_t c = 0; c < result.cameras.size() && c < 2; ++c)
    for (const calib::ViewError& v : result.cameras[c].per_view) worst.push_back({int(c), v.view, v.rms_px});
  std::sort(worst.begin(), worst.end(), [](const Worst& a, const Worst& b) { return a.rms_px > b.rms_px; });
  if (worst.size() > std::size_t(kWorstViews)) worst.resize(std::size_t(kWorstViews));
  worst_title_->setText(QString("<b>Worst views</b> (sample numbers as in the sample list; each corner's error "
                                "drawn in red, %1× its length)")
                            .arg(kErrorMagnification, 0, 'f', 0));
  for (const Worst& w : worst) {
    const calib::CameraIntrinsicResult& cam = result.cameras[std::size_t(w.camera)];
    const QString text = QString("%1 sample %2: RMS %3 px")
                             .arg(QString::fromStdString(cam.calibration.label))
                             .arg(w.view + 1)
                             .arg(w.rms_px, 0, 'f', 2);
    worst_.push_back(text);
    auto* box = new QWidget;
    auto* v = new QVBoxLayout(box);
    v->setContentsMargins(0, 0, 0, 0);
    auto* picture = new QLabel;
    if (collector && w.view >= 0 && std::size_t(w.view) < collector->samples().size())
      picture->setPixmap(viewWithErrors(collector->samples()[std::size_t(w.view)], w.camera, cam, w.view, 240));
    v->addWidget(picture);
    v->addWidget(new QLabel(text));
    worst_row_->addWidget(box);
  }
  worst_row_->addStretch(1);
}

}  // namespace telesphere::console
