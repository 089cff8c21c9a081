// SPDX-License-Identifier: MIT
/// @brief Both cameras, small and live (the robot's reduced preview stream, not the 2×4K
///        stream), with the current visual mode and sphere radius and how old the picture is.
#pragma once

#include <QWidget>

class QLabel;

namespace telesphere::console {

class ConsoleSession;

class CameraPreviewPanel : public QWidget {
  Q_OBJECT

 public:
  explicit CameraPreviewPanel(ConsoleSession& session, QWidget* parent = nullptr);
  void refresh();
  QString caption() const;

 private:
  void showImages();

  ConsoleSession& session_;
  QLabel* left_;
  QLabel* right_;
  QLabel* caption_;
};

}  // namespace telesphere::console
