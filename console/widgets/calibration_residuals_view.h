// SPDX-License-Identifier: MIT
/// @brief The Residuals tab of the Calibration panel (issue #15): every corner's reprojection
///        error against the corner's polar angle, per camera, with the RMS of each 10° bin as a
///        line (a model that fits the centre but not the rim shows here first); underneath, the
///        worst views, each camera's thumbnail with every corner's error drawn as a line,
///        magnified by a stated factor.
#pragma once

#include <QWidget>

#include "calib/intrinsic_calibration.h"
#include "console/calibration/intrinsics_collector.h"

class QCustomPlot;
class QHBoxLayout;
class QLabel;

namespace telesphere::console {

class CalibrationResidualsView : public QWidget {
  Q_OBJECT

 public:
  /// Error lines on the thumbnails are this many times their length in pixels of the image.
  static constexpr double kErrorMagnification = 40.0;
  /// How many of the worst views (over both cameras) are drawn.
  static constexpr int kWorstViews = 4;

  explicit CalibrationResidualsView(QWidget* parent = nullptr);

  /// Shows `result`; `collector` holds the samples the result was solved from (same order), for
  /// the thumbnails (none drawn when null).
  void showResult(const calib::IntrinsicResult& result, const calibration::IntrinsicsCollector* collector);
  void clear();

  QCustomPlot* plot() const { return plot_; }
  /// The worst views shown, as "cam_l view 7: RMS 0.41 px", worst first.
  QStringList worstViews() const { return worst_; }

 private:
  QCustomPlot* plot_ = nullptr;
  QLabel* worst_title_ = nullptr;
  QHBoxLayout* worst_row_ = nullptr;
  QStringList worst_;
};

}  // namespace telesphere::console
