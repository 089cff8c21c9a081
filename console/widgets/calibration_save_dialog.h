// SPDX-License-Identifier: MIT
/// @brief The save of the calibration panels' results: where, and in which of our three formats
///        (telesphere YAML, kalibr camchain, Basalt JSON), chosen by the dialog's filter; the
///        write; the Save button that asks and shows a failure in the panel's status line.
#pragma once

#include <QFileDialog>
#include <QLabel>
#include <QPushButton>
#include <QString>
#include <functional>

#include "calib/calibration_file.h"

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

/// Writes `calibration` to `path` in `format` ("telesphere", "kalibr", "basalt"); false with the
/// reason in *error.
inline bool saveCalibrationAs(const calib::SystemCalibration& calibration, const QString& path, const QString& format,
                              QString* error) {
  const auto f = calib::parseFormatName(format.toStdString());
  if (!f) {
    *error = "unknown format " + format + " (telesphere, kalibr or basalt)";
    return false;
  }
  if (auto e = calib::saveCalibrationFile(calibration, path.toStdString(), *f)) {
    *error = QString::fromStdString(e->describe());
    return false;
  }
  return true;
}

/// `button` asks where and how (askCalibrationSavePath), then calls `save`; its error goes to
/// `status` in red.
inline void connectCalibrationSave(QPushButton* button, QWidget* panel, QLabel* status,
                                   std::function<bool(const QString& path, const QString& format, QString* error)> save) {
  QObject::connect(button, &QPushButton::clicked, panel, [panel, status, save = std::move(save)] {
    QString path, format, error;
    if (!askCalibrationSavePath(panel, &path, &format)) return;
    if (!save(path, format, &error)) status->setText("<span style='color:#b00'>" + error.toHtmlEscaped() + "</span>");
  });
}

}  // namespace telesphere::console
