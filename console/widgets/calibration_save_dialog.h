// SPDX-License-Identifier: MIT
/// @brief The save dialog of the calibration panels: where, and in which of our three formats
///        (telesphere YAML, kalibr camchain, Basalt JSON), chosen by the dialog's filter.
#pragma once

#include <QFileDialog>
#include <QString>

namespace telesphere::console {

/// False when the user cancelled; otherwise *path and *format ("telesphere", "kalibr", "basalt").
inline bool askCalibrationSavePath(QWidget* parent, QString* path, QString* format) {
  QString filter;
  *path = QFileDialog::getSaveFileName(parent, "Save calibration", "calibration.yaml",
                                       "telesphere (*.yaml);;kalibr camchain (*.yaml);;Basalt (*.json)", &filter);
  if (path->isEmpty()) return false;
  *format = filter.startsWith("kalibr") ? "kalibr" : filter.startsWith("Basalt") ? "basalt" : "telesphere";
  return true;
}

}  // namespace telesphere::console
