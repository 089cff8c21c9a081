// SPDX-License-Identifier: MIT
/// @brief Running the Qt event loop in widget tests and helpers: until a condition holds, or
///        for a while. Qt only (no gtest), so helper programs use it too.
#pragma once

#include <QApplication>
#include <QElapsedTimer>
#include <QThread>
#include <functional>

namespace telesphere::console::test_rig {

/// Runs the event loop until `condition` holds or `timeout_ms` passed; true when it held.
inline bool pumpUntil(const std::function<bool()>& condition, int timeout_ms = 30000) {
  QElapsedTimer timer;
  timer.start();
  while (timer.elapsed() < timeout_ms) {
    QApplication::processEvents(QEventLoop::AllEvents, 20);
    if (condition()) return true;
    QThread::msleep(5);
  }
  return condition();
}

inline void pumpFor(int ms) {
  pumpUntil([] { return false; }, ms);
}

}  // namespace telesphere::console::test_rig
