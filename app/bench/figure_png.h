// SPDX-License-Identifier: MIT
/// @brief Figures of the benchmarks as PNG with the plotting library the console uses
///        (QCustomPlot, offscreen): lines or points, axes with units, a legend. Needs a
///        QApplication (ensureQtApplication()).
#pragma once

#include <QColor>
#include <string>
#include <vector>

namespace telesphere::bench {

struct FigureSeries {
  std::string name;  ///< legend text
  std::vector<double> x, y;
  QColor colour = Qt::blue;
  bool points = false;  ///< markers only (else a line)
  bool right_axis = false;  ///< on the right value axis
  bool dashed = false;
};

struct Figure {
  std::string title, x_label, y_label, y2_label;  ///< labels with units
  std::vector<FigureSeries> series;
  bool log_x = false;
  int width = 1000, height = 560;
  bool legend_left = false;  ///< legend in the top-left corner (else top-right)
};

/// Creates the QApplication the figures need (offscreen unless a display is set), once.
void ensureQtApplication();
/// Writes the figure; false when the PNG could not be written.
bool writeFigurePng(const Figure& figure, const std::string& path);

}  // namespace telesphere::bench
