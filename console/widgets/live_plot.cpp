// SPDX-License-Identifier: MIT
/// @brief LivePlot: toolbar + QCustomPlot fed by decimated series.
#include "console/widgets/live_plot.h"

#include <qcustomplot.h>

#include <QComboBox>
#include <QElapsedTimer>
#include <QFile>
#include <QFileDialog>
#include <QHBoxLayout>
#include <QLabel>
#include <QMessageBox>
#include <QTextStream>
#include <QToolButton>
#include <QVBoxLayout>
#include <cmath>
#include <limits>

namespace telesphere::console {
namespace {

QString csvField(const QString& text) {
  if (!text.contains(',') && !text.contains('"') && !text.contains('\n')) return text;
  QString quoted = text;
  quoted.replace("\"", "\"\"");
  return "\"" + quoted + "\"";
}

}  // namespace

const std::vector<double>& LivePlot::windowChoices() {
  static const std::vector<double> choices = {5, 10, 30, 60, 120, 300, 600};
  return choices;
}

LivePlot::LivePlot(telemetry::SeriesStore& store, std::function<double()> now, PlotSpec spec, QWidget* parent)
    : QWidget(parent), store_(store), now_(std::move(now)), spec_(std::move(spec)) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(2, 2, 2, 2);
  layout->setSpacing(2);
  auto* bar = new QHBoxLayout;
  auto* title = new QLabel("<b>" + spec_.title.toHtmlEscaped() + "</b>");
  bar->addWidget(title);
  bar->addStretch(1);
  pause_button_ = new QToolButton;
  pause_button_->setText("Pause");
  pause_button_->setCheckable(true);
  pause_button_->setToolTip("Freeze the view (data keeps arriving); zooming or dragging pauses too");
  connect(pause_button_, &QToolButton::toggled, this, [this](bool on) { setPaused(on); });
  bar->addWidget(pause_button_);
  bar->addWidget(new QLabel("window"));
  window_box_ = new QComboBox;
  for (double s : windowChoices()) window_box_->addItem(QString("%1 s").arg(s), s);
  window_box_->setCurrentIndex(2);
  connect(window_box_, &QComboBox::currentIndexChanged, this,
          [this](int i) { setWindowSeconds(window_box_->itemData(i).toDouble()); });
  bar->addWidget(window_box_);
  const auto button = [&](const QString& text, const QString& tip, auto slot) {
    auto* b = new QToolButton;
    b->setText(text);
    b->setToolTip(tip);
    connect(b, &QToolButton::clicked, this, slot);
    bar->addWidget(b);
  };
  button("Clear", "Empty this plot's buffers", [this] { clear(); });
  button("CSV…", "Save the visible samples (not decimated) as CSV", [this] {
    chooseFile("CSV (*.csv)", "csv", [this](const QString& p, QString* e) { return exportCsv(p, e); });
  });
  button("PNG…", "Save the plot as PNG", [this] {
    chooseFile("PNG (*.png)", "png", [this](const QString& p, QString* e) { return exportPng(p, e); });
  });
  button("PDF…", "Save the plot as PDF", [this] {
    chooseFile("PDF (*.pdf)", "pdf", [this](const QString& p, QString* e) { return exportPdf(p, e); });
  });
  layout->addLayout(bar);

  plot_ = new QCustomPlot(this);
  plot_->setMinimumSize(320, 180);
  plot_->setNoAntialiasingOnDrag(true);

  plot_->setInteractions(QCP::iRangeDrag | QCP::iRangeZoom);
  plot_->axisRect()->setRangeDrag(Qt::Horizontal);
  plot_->axisRect()->setRangeZoom(Qt::Horizontal);
  plot_->xAxis->setLabel("time before now [s] (samples at their source time)");
  plot_->yAxis->setLabel(spec_.y_label);
  if (!spec_.y2_label.isEmpty()) {
    plot_->yAxis2->setVisible(true);
    plot_->yAxis2->setLabel(spec_.y2_label);
  }
  plot_->legend->setVisible(true);
  plot_->legend->setFont(QFont(font().family(), 8));
  plot_->legend->setBrush(QColor(255, 255, 255, 210));
  plot_->axisRect()->insetLayout()->setInsetAlignment(0, Qt::AlignTop | Qt::AlignLeft);
  // The curves get a layer with its own paint buffer: when only data changed (the live axis
  // shows time before now, so its range stays put), just that layer is redrawn; grid, axes,
  // labels and legend are reused.
  plot_->addLayer("curves", plot_->layer("main"), QCustomPlot::limAbove);
  plot_->layer("curves")->setMode(QCPLayer::lmBuffered);
  for (const PlotLine& line : spec_.lines) {
    QCPGraph* g = plot_->addGraph(plot_->xAxis, line.right_axis ? plot_->yAxis2 : plot_->yAxis);
    g->setLayer("curves");
    g->setName(line.legend);
    g->setPen(QPen(line.color, 0));  // cosmetic 1 px: the raster engine's fast path
    g->setAdaptiveSampling(false);  // the store decimated already
    if (line.fill_to_previous && !graphs_.empty()) {
      QColor fill = line.color;
      fill.setAlpha(110);
      g->setBrush(fill);
      g->setChannelFillGraph(graphs_.back());
    } else if (line.fill_to_zero) {
      QColor fill = line.color;
      fill.setAlpha(110);
      g->setBrush(fill);
    }
    if (line.impulses) g->setLineStyle(QCPGraph::lsImpulse);
    graphs_.push_back(g);
  }
  setAntialiased(false);
  // A user zoom or drag pauses the live view so the range stays where they put it.
  connect(plot_->xAxis, qOverload<const QCPRange&>(&QCPAxis::rangeChanged), this, [this](const QCPRange&) {
    if (!programmatic_range_ && !paused_) setPaused(true);
  });
  layout->addWidget(plot_, 1);
}

void LivePlot::addMarker(double t, const QString& text) {
  auto* line = new QCPItemStraightLine(plot_);
  line->setLayer("curves");
  line->setPen(QPen(QColor(90, 90, 90), 0, Qt::DashLine));
  auto* label = new QCPItemText(plot_);
  label->setLayer("curves");
  label->setText(text);
  label->setFont(QFont(font().family(), 7));
  label->setColor(QColor(60, 60, 60));
  label->setPositionAlignment(Qt::AlignLeft | Qt::AlignTop);
  label->position->setTypeY(QCPItemPosition::ptAxisRectRatio);
  markers_.push_back({t, line, label});
  while (markers_.size() > kMaxMarkers) {
    plot_->removeItem(markers_.front().line);
    plot_->removeItem(markers_.front().label);
    markers_.pop_front();
  }
}

void LivePlot::setAntialiased(bool on) {
  for (QCPGraph* g : graphs_) {
    g->setAntialiased(on);
    g->setAntialiasedFill(on);
  }
}

void LivePlot::setPaused(bool paused) {
  if (paused == paused_) return;
  paused_ = paused;
  plot_->xAxis->setLabel(paused ? "time before the pause [s] (samples at their source time)"
                                : "time before now [s] (samples at their source time)");
  pause_button_->blockSignals(true);
  pause_button_->setChecked(paused);
  pause_button_->setText(paused ? "Live" : "Pause");
  pause_button_->blockSignals(false);
  emit pausedChanged(paused);
  if (!paused) refresh();
}

void LivePlot::setWindowSeconds(double seconds) {
  window_s_ = seconds;
  for (int i = 0; i < window_box_->count(); ++i)
    if (window_box_->itemData(i).toDouble() == seconds && window_box_->currentIndex() != i) {
      window_box_->blockSignals(true);
      window_box_->setCurrentIndex(i);
      window_box_->blockSignals(false);
    }
  if (paused_) {  // keep the right edge, show the new width
    const double x1 = plot_->xAxis->range().upper;
    programmatic_range_ = true;
    plot_->xAxis->setRange(x1 - seconds, x1);
    programmatic_range_ = false;
  }
  refresh();
}

std::pair<double, double> LivePlot::visibleRange() const {
  return {origin_ + plot_->xAxis->range().lower, origin_ + plot_->xAxis->range().upper};
}

void LivePlot::clear() {
  for (const PlotLine& line : spec_.lines)
    if (const telemetry::SeriesInfo* info = store_.info(line.series)) store_.series(*info).clear();
  store_.markChanged();
  refresh();
}

void LivePlot::refresh() {
  QElapsedTimer timer;
  timer.start();
  double t0, t1;
  if (paused_) {
    std::tie(t0, t1) = visibleRange();
  } else {
    t1 = now_();
    t0 = t1 - window_s_;
    origin_ = t1;
    programmatic_range_ = true;
    plot_->xAxis->setRange(-window_s_, 0.0);
    programmatic_range_ = false;
  }
  // Min/max per pixel column, on a grid fixed in time while the window and the width are (so
  // the decimators' final columns stay valid); without decimation every sample in view.
  const int columns = std::max(16, plot_->axisRect()->width());
  const double width = (paused_ ? t1 - t0 : window_s_) / columns;
  decimators_.resize(spec_.lines.size());
  std::vector<telemetry::Sample> points;
  QVector<QCPGraphData> data;
  double lo[2] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  double hi[2] = {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  last_points_ = 0;
  for (std::size_t i = 0; i < spec_.lines.size(); ++i) {
    const PlotLine& line = spec_.lines[i];
    data.clear();
    if (const telemetry::TimeSeries* s = store_.find(line.series)) {
      if (decimate_) {
        decimators_[i].decimate(*s, t0, t1, width, points);
      } else {
        const auto [first, last] = s->indexRange(t0, t1);
        points.clear();
        for (std::size_t k = first; k < last; ++k) points.push_back((*s)[k]);
      }
      data.reserve(int(points.size()));
      // Every column's extremes are among the points: the value range needs no second scan.
      const int axis = line.right_axis ? 1 : 0;
      for (const telemetry::Sample& p : points) {
        data.push_back(QCPGraphData(p.t - origin_, p.v));
        if (p.t >= t0 && p.t <= t1 && std::isfinite(p.v)) {
          lo[axis] = std::min(lo[axis], p.v);
          hi[axis] = std::max(hi[axis], p.v);
        }
      }
    }
    last_points_ += std::size_t(data.size());
    graphs_[i]->data()->set(data, true);
  }
  for (int axis = 0; axis < 2; ++axis) {
    QCPAxis* a = axis == 0 ? plot_->yAxis : plot_->yAxis2;
    if (!std::isfinite(lo[axis])) continue;
    // From zero where everything is positive (latencies, speeds), else around the data. The
    // range grows at once and shrinks only when the data use less than half of it, so the axis
    // (and its tick labels, whose width changes relayout the plot) mostly stays still and only
    // the curves are redrawn.
    const double low = lo[axis] >= 0 ? 0.0 : lo[axis];
    const double high = hi[axis] > low ? hi[axis] : low + 1.0;
    const QCPRange now = a->range();
    const bool contains = low >= now.lower && high <= now.upper;
    const bool roomy = (high - low) < 0.5 * (now.upper - now.lower);
    if (!contains || roomy) {
      const double pad = 0.25 * (high - low);
      a->setRange(lo[axis] >= 0 ? 0.0 : low - pad, high + pad);
    }
  }
  for (std::size_t m = 0; m < markers_.size(); ++m) {  // x is time before the origin: they move
    const double x = markers_[m].t - origin_;
    markers_[m].line->point1->setCoords(x, 0.0);
    markers_[m].line->point2->setCoords(x, 1.0);
    markers_[m].label->position->setCoords(x, 0.02 + 0.045 * double(m % 4));
  }
  const QCPRange x = plot_->xAxis->range(), y = plot_->yAxis->range(), y2 = plot_->yAxis2->range();
  const bool same_frame = x.lower == drawn_x_[0] && x.upper == drawn_x_[1] && y.lower == drawn_y_[0] &&
                          y.upper == drawn_y_[1] && y2.lower == drawn_y2_[0] && y2.upper == drawn_y2_[1] &&
                          plot_->size() == drawn_size_;
  if (same_frame) {
    plot_->layer("curves")->replot();
    plot_->repaint();  // compose the layers now, as the full replot does (and so it is timed)
  } else {
    plot_->replot(QCustomPlot::rpImmediateRefresh);
    drawn_x_[0] = x.lower, drawn_x_[1] = x.upper, drawn_y_[0] = y.lower, drawn_y_[1] = y.upper;
    drawn_y2_[0] = y2.lower, drawn_y2_[1] = y2.upper;
    drawn_size_ = plot_->size();
  }
  last_refresh_ms_ = double(timer.nsecsElapsed()) * 1e-6;
}

bool LivePlot::exportCsv(const QString& path, QString* error) const {
  QFile file(path);
  if (!file.open(QIODevice::WriteOnly | QIODevice::Truncate | QIODevice::Text)) {
    *error = path + ": " + file.errorString();
    return false;
  }
  QTextStream out(&file);
  out << "series,label,unit,t_s,value\n";
  const auto [t0, t1] = visibleRange();
  for (const PlotLine& line : spec_.lines) {
    const telemetry::TimeSeries* s = store_.find(line.series);
    const telemetry::SeriesInfo* info = store_.info(line.series);
    if (!s || !info) continue;
    const auto [first, last] = s->indexRange(t0, t1);
    const QString prefix = csvField(QString::fromStdString(info->name)) + "," +
                           csvField(QString::fromStdString(info->label)) + "," +
                           csvField(QString::fromStdString(info->unit)) + ",";
    for (std::size_t i = first; i < last; ++i)
      out << prefix << QString::number((*s)[i].t, 'f', 6) << "," << QString::number((*s)[i].v, 'g', 10) << "\n";
  }
  out.flush();
  if (file.error() != QFile::NoError) {
    *error = path + ": " + file.errorString();
    return false;
  }
  return true;
}

bool LivePlot::exportPng(const QString& path, QString* error, int width, int height) {
  if (plot_->savePng(path, width, height)) return true;
  *error = path + ": cannot write the PNG";
  return false;
}

bool LivePlot::exportPdf(const QString& path, QString* error) {
  if (plot_->savePdf(path)) return true;
  *error = path + ": cannot write the PDF";
  return false;
}

void LivePlot::chooseFile(const QString& filter, const QString& suffix,
                          const std::function<bool(const QString&, QString*)>& write) {
  QString path = QFileDialog::getSaveFileName(this, "Export " + spec_.title, spec_.title + "." + suffix, filter,
                                              nullptr, QFileDialog::DontUseNativeDialog);
  if (path.isEmpty()) return;
  if (!path.endsWith("." + suffix)) path += "." + suffix;
  QString error;
  if (!write(path, &error)) QMessageBox::warning(this, "Export failed", error);
}

}  // namespace telesphere::console
