// SPDX-License-Identifier: MIT
/// @brief The system at a glance: robot and XR app (connected / silent / gone, for how long),
///        clock offset and round trip, each camera (fps, drops by reason, exposure, reconnects,
///        last error), the video path, the arm and head loop, the XR app's figures, and the
///        link's and the telemetry's own health. Rows that need attention are red.
#pragma once

#include <QString>
#include <QWidget>
#include <map>

class QTreeWidget;
class QTreeWidgetItem;

namespace telesphere::console {

class ConsoleSession;

class HealthPanel : public QWidget {
  Q_OBJECT

 public:
  explicit HealthPanel(ConsoleSession& session, QWidget* parent = nullptr);
  void refresh();
  /// The value shown in row `key` of `section` ("" when there is no such row), for tests.
  QString value(const QString& section, const QString& key) const;

 private:
  void setRow(const QString& section, const QString& key, const QString& value, bool warn = false);

  ConsoleSession& session_;
  QTreeWidget* tree_;
  std::map<QString, QTreeWidgetItem*> sections_;
};

}  // namespace telesphere::console
