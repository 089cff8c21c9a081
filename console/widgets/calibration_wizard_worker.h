// SPDX-License-Identifier: MIT
/// @brief The scaffolding both calibration wizard panels (Calibration, Hand-eye) share: one run at
///        a time in a worker thread, its cancel flag (the procedures poll it), its result handed
///        to the panel on the GUI thread, and the worker's log lines appended to the panel's Log
///        tab. The window never waits on a run; the panel's destructor stops it (cancel, join)
///        before anything the worker uses is freed.
#pragma once

#include <QMetaObject>
#include <QObject>
#include <QPlainTextEdit>
#include <QString>
#include <atomic>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>

namespace telesphere::console {

/// A read-only log for a wizard's Log tab (the last 2000 lines).
inline QPlainTextEdit* newCalibrationLog(const QString& object_name) {
  auto* log = new QPlainTextEdit;
  log->setReadOnly(true);
  log->setMaximumBlockCount(2000);
  log->setObjectName(object_name);
  return log;
}

/// A log callback for a worker: each line appended to `log` on `owner`'s (the GUI) thread.
inline std::function<void(const std::string&)> calibrationLogSink(QObject* owner, QPlainTextEdit* log) {
  return [owner, log](const std::string& line) {
    QMetaObject::invokeMethod(owner, [log, text = QString::fromStdString(line)] { log->appendPlainText(text); },
                              Qt::QueuedConnection);
  };
}

/// One run of a wizard at a time in a worker thread; `Outcome` is the procedure's result.
template <class Outcome>
class CalibrationWizardWorker {
 public:
  /// `owner` (the panel) is where the end of a run is announced, on its thread.
  explicit CalibrationWizardWorker(QObject* owner) : owner_(owner) {}
  ~CalibrationWizardWorker() { stop(); }
  CalibrationWizardWorker(const CalibrationWizardWorker&) = delete;
  CalibrationWizardWorker& operator=(const CalibrationWizardWorker&) = delete;

  /// A run was launched and has not ended yet.
  bool running() const { return thread_.joinable() && !finished_; }
  /// The flag the procedures poll (their options' `cancel`); reset by launch().
  std::atomic<bool>* cancelFlag() { return &cancel_; }
  bool cancelled() const { return cancel_; }
  void cancel() { cancel_ = true; }
  /// Cancels a run and waits for its worker (the panel's destructor).
  void stop() {
    cancel_ = true;
    join();
  }

  /// Runs `work` in a new worker (after the previous one ended); when it returns, its result is
  /// kept for take() and `finished` runs on the owner's thread.
  void launch(std::function<Outcome()> work, std::function<void()> finished) {
    join();
    cancel_ = false;
    finished_ = false;
    thread_ = std::thread([this, work = std::move(work), finished = std::move(finished)] {
      Outcome result = work();
      {
        std::lock_guard lock(mutex_);
        pending_ = std::move(result);
      }
      finished_ = true;
      QMetaObject::invokeMethod(owner_, finished, Qt::QueuedConnection);
    });
  }

  /// On the owner's thread once a run ended: its result (empty when already taken).
  std::optional<Outcome> take() {
    join();
    std::lock_guard lock(mutex_);
    std::optional<Outcome> result = std::move(pending_);
    pending_.reset();
    return result;
  }

 private:
  void join() {
    if (thread_.joinable()) thread_.join();
  }

  QObject* owner_;
  std::thread thread_;
  std::atomic<bool> cancel_{false};
  std::atomic<bool> finished_{true};
  std::mutex mutex_;
  std::optional<Outcome> pending_;
};

}  // namespace telesphere::console
