// SPDX-License-Identifier: MIT
/// @brief A live plot of some of the console's series (QCustomPlot), with the controls a
///        supervisor expects: pause and resume, zoom and drag in time (which pause), a time
///        window, clear, export of the visible data as CSV and of the plot as PNG or PDF.
///
/// It never draws raw data: refresh() draws each series' min/max decimation over the visible time
/// at the plot's pixel width (≤ 2 points per pixel column, gaps as NaN breaks; a ColumnDecimator
/// per curve keeps the final columns, so a scrolling redraw looks only at new samples): a redraw
/// costs the same at 10 Hz or 10 kHz input. The caller decides when to refresh (one coalesced
/// timer for all plots, only the visible ones).
#pragma once

#include <QColor>
#include <QString>
#include <QWidget>
#include <deque>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "console/telemetry/column_decimator.h"
#include "console/telemetry/series_store.h"

class QCustomPlot;
class QCPGraph;
class QCPItemStraightLine;
class QCPItemText;
class QComboBox;
class QToolButton;

namespace telesphere::console {

/// One curve: a series, how it is drawn and on which axis.
struct PlotLine {
  std::string series;
  QString legend;
  QColor color;
  bool right_axis = false;        ///< on the right-hand value axis
  bool fill_to_previous = false;  ///< a band between this curve and the previous line (stacked)
  bool fill_to_zero = false;      ///< a band down to zero (the first of a stack)
  bool impulses = false;          ///< vertical lines from zero (counts)
};

struct PlotSpec {
  QString title;
  QString y_label;   ///< with unit, e.g. "latency since capture [ms]"
  QString y2_label;  ///< right axis (empty: none)
  std::vector<PlotLine> lines;
};

class LivePlot : public QWidget {
  Q_OBJECT

 public:
  /// `now` gives the plot clock's present (s); the store must outlive the plot.
  LivePlot(telemetry::SeriesStore& store, std::function<double()> now, PlotSpec spec, QWidget* parent = nullptr);

  /// Redraws from the store: live, the window ends now; paused, it stays where it is.
  void refresh();

  bool paused() const { return paused_; }
  void setPaused(bool paused);
  double windowSeconds() const { return window_s_; }
  void setWindowSeconds(double seconds);
  /// The visible time interval (plot clock, s; the axis shows it relative to now, or to the
  /// moment of pausing).
  std::pair<double, double> visibleRange() const;
  /// Empties this plot's series.
  void clear();
  /// Marks a moment (plot clock) with a dashed vertical line and a label, e.g. a setting the
  /// robot accepted; the newest kMaxMarkers are kept.
  void addMarker(double t, const QString& text);
  static constexpr std::size_t kMaxMarkers = 20;
  /// Off: every visible sample goes to QCustomPlot (the benchmark's comparison; on by default).
  void setDecimation(bool on) { decimate_ = on; }
  /// Antialiased curves and fills look smoother; with the 1-px cosmetic pens they cost about
  /// 10 % more redraw time at p50 and 25 % at p99 on Qt's raster engine (telesphere-bench
  /// console, 10 s window); off by default.
  void setAntialiased(bool on);

  /// Every sample of the plot's series in the visible interval, undecimated: one row per sample
  /// (series, label, unit, t_s, value). False with *error when the file cannot be written.
  bool exportCsv(const QString& path, QString* error) const;
  bool exportPng(const QString& path, QString* error, int width = 0, int height = 0);
  bool exportPdf(const QString& path, QString* error);

  const PlotSpec& spec() const { return spec_; }
  QCustomPlot* plot() const { return plot_; }
  double lastRefreshMs() const { return last_refresh_ms_; }
  /// Points handed to QCustomPlot by the last refresh, all curves together.
  std::size_t lastPointCount() const { return last_points_; }

  static const std::vector<double>& windowChoices();

 signals:
  void pausedChanged(bool paused);

 private:
  void chooseFile(const QString& filter, const QString& suffix,
                  const std::function<bool(const QString&, QString*)>& write);

  telemetry::SeriesStore& store_;
  std::function<double()> now_;
  PlotSpec spec_;
  QCustomPlot* plot_;
  std::vector<QCPGraph*> graphs_;
  std::vector<telemetry::ColumnDecimator> decimators_;  ///< one per curve
  struct Marker {
    double t;
    QCPItemStraightLine* line;
    QCPItemText* label;
  };
  std::deque<Marker> markers_;
  QToolButton* pause_button_;
  QComboBox* window_box_;
  bool paused_ = false;
  bool decimate_ = true;
  /// The plot clock time drawn at x = 0: now while live, the moment of pausing while paused. The
  /// axis shows time before it, so its tick labels stay the same while the view scrolls (no
  /// text to lay out anew every frame).
  double origin_ = 0.0;
  double window_s_ = 30.0;
  double last_refresh_ms_ = 0.0;
  std::size_t last_points_ = 0;
  bool programmatic_range_ = false;
  /// Axis ranges of the last full replot: while they stay, only the curves' layer is redrawn.
  double drawn_x_[2] = {0, 0}, drawn_y_[2] = {0, 0}, drawn_y2_[2] = {0, 0};
  QSize drawn_size_;
};

}  // namespace telesphere::console
