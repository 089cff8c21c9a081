// SPDX-License-Identifier: MIT
/// @brief The red banner above everything: every fault not yet acknowledged (still holding or
///        cleared, and since when), with one button to acknowledge them. Hidden when there is
///        nothing to acknowledge.
#pragma once

#include <QFrame>

class QLabel;
class QPushButton;

namespace telesphere::console {

class ConsoleSession;

class FaultBanner : public QFrame {
  Q_OBJECT

 public:
  explicit FaultBanner(ConsoleSession& session, QWidget* parent = nullptr);
  void refresh();
  QString text() const;
  QPushButton* acknowledgeButton() const { return acknowledge_; }

 private:
  ConsoleSession& session_;
  QLabel* label_;
  QPushButton* acknowledge_;
};

}  // namespace telesphere::console
