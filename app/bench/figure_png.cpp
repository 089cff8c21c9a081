// SPDX-License-Identifier: MIT
/// @brief Figures as PNG through QCustomPlot (see figure_png.h).
#include "app/bench/figure_png.h"

#include <QApplication>
#include <cstdlib>
#include <memory>
#include <qcustomplot.h>

namespace telesphere::bench {

void ensureQtApplication() {
  if (QApplication::instance() != nullptr) return;
  if (!std::getenv("QT_QPA_PLATFORM") && !std::getenv("DISPLAY")) setenv("QT_QPA_PLATFORM", "offscreen", 1);
  static int argc = 1;
  static char name[] = "telesphere-bench";
  static char* argv[] = {name, nullptr};
  static std::unique_ptr<QApplication> app = std::make_unique<QApplication>(argc, argv);
}

bool writeFigurePng(const Figure& figure, const std::string& path) {
  ensureQtApplication();
  QCustomPlot plot;
  plot.resize(figure.width, figure.height);
  plot.plotLayout()->insertRow(0);
  plot.plotLayout()->addElement(0, 0, new QCPTextElement(&plot, QString::fromStdString(figure.title),
                                                         QFont("sans", 11, QFont::Bold)));
  plot.xAxis->setLabel(QString::fromStdString(figure.x_label));
  plot.yAxis->setLabel(QString::fromStdString(figure.y_label));
  if (figure.log_x) {
    plot.xAxis->setScaleType(QCPAxis::stLogarithmic);
    plot.xAxis->setTicker(QSharedPointer<QCPAxisTickerLog>(new QCPAxisTickerLog));
  }
  bool any_right = false, first_left = true, first_right = true, first_key = true;
  for (const FigureSeries& s : figure.series) {
    QCPAxis* value_axis = s.right_axis ? plot.yAxis2 : plot.yAxis;
    any_right |= s.right_axis;
    QCPGraph* g = plot.addGraph(plot.xAxis, value_axis);
    g->setName(QString::fromStdString(s.name));
    QPen pen(s.colour);
    pen.setWidthF(1.6);
    if (s.dashed) pen.setStyle(Qt::DashLine);
    g->setPen(pen);
    if (s.points) {
      g->setLineStyle(QCPGraph::lsNone);
      g->setScatterStyle(QCPScatterStyle(QCPScatterStyle::ssCircle, s.colour, 5));
    }
    g->setData(QVector<double>(s.x.begin(), s.x.end()), QVector<double>(s.y.begin(), s.y.end()));
    if (s.x.empty()) continue;
    bool& first_value = s.right_axis ? first_right : first_left;
    g->rescaleKeyAxis(!first_key);
    g->rescaleValueAxis(!first_value);
    first_key = first_value = false;
  }
  if (any_right) {
    plot.yAxis2->setVisible(true);
    plot.yAxis2->setLabel(QString::fromStdString(figure.y2_label));
  }
  // Some room around the data.
  for (QCPAxis* axis : {plot.yAxis, plot.yAxis2}) {
    const QCPRange r = axis->range();
    axis->setRange(r.lower - 0.05 * r.size(), r.upper + 0.05 * r.size());
  }
  plot.legend->setVisible(true);
  plot.legend->setFont(QFont("sans", 9));
  plot.axisRect()->insetLayout()->setInsetAlignment(
      0, Qt::AlignTop | (figure.legend_left ? Qt::AlignLeft : Qt::AlignRight));
  return plot.savePng(QString::fromStdString(path), figure.width, figure.height);
}

}  // namespace telesphere::bench
