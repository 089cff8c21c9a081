// SPDX-License-Identifier: MIT
/// @brief The Internet link panel (DESIGN.md §9): the media path now (receiver, estimate, target,
///        round trip, loss, queue, frame age, the stream's frame rate, scale and quality and what
///        limits them, every rate and stream decision counted by reason), the supervisor's cap on
///        the path's rate, and the link's four live graphs (linkPlots).
#pragma once

#include <QString>
#include <QWidget>
#include <functional>
#include <vector>

class QDoubleSpinBox;
class QLabel;
class QPushButton;

namespace telesphere::console {

class ConsoleSession;
class LivePlot;

class LinkPanel : public QWidget {
  Q_OBJECT

 public:
  /// `window_s`: the graphs' time window.
  LinkPanel(ConsoleSession& session, double window_s, QWidget* parent = nullptr);

  /// The figures from the newest health and XR stats (the graphs redraw on their own timer).
  void refresh();
  const std::vector<LivePlot*>& plots() const { return plots_; }
  /// The figures as shown, for tests.
  QString summaryText() const;
  QString capText() const;
  /// What the supervisor asks for: a cap (Mbit/s) or none (0).
  void requestCap(double cap_mbit);

 private:
  ConsoleSession& session_;
  QLabel* summary_;
  QLabel* decisions_;
  QLabel* cap_now_;
  QLabel* reply_;
  QDoubleSpinBox* cap_;
  QPushButton* set_cap_;
  QPushButton* lift_cap_;
  std::vector<LivePlot*> plots_;
};

}  // namespace telesphere::console
