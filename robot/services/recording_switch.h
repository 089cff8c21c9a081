// SPDX-License-Identifier: MIT
/// @brief The robot's recording switch (issue #18): one session recording at a time on the
///        robot's link — from the command line (--record FILE), a console request (the record
///        folder's NAME.mcap), or a study trial (the trial indicator's recording name) — with its
///        state for replies and health. Never overwrites a file; a name is a plain file name.
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "robot/link/link_server.h"
#include "robot/record/link_recorder.h"

namespace telesphere::robot::services {

class RecordingSwitch {
 public:
  /// `dir`: where named recordings go (empty: only startFile); created when first needed.
  RecordingSwitch(link::LinkServer& server, std::string dir, record::LinkRecorderOptions options);
  /// Stops and finishes a recording in progress.
  ~RecordingSwitch();
  RecordingSwitch(const RecordingSwitch&) = delete;
  RecordingSwitch& operator=(const RecordingSwitch&) = delete;

  /// Where each recording gets the calibration in use when it starts (attached to the file; later
  /// changes are attached as the control replies that make them pass). Empty: none attached.
  void setCalibrationSource(std::function<std::optional<link::proto::CalibrationInUse>()> source);

  /// Records to `path` (a new file). False with the reason (recording already, file exists, …).
  /// `metadata` joins the options' in the file's "telesphere" metadata record (a study trial's).
  bool startFile(const std::string& path, std::string* error, const std::map<std::string, std::string>& metadata = {});
  /// Records to dir/NAME.mcap; NAME: letters, digits, '-', '_', '.' (not starting with '.').
  bool startNamed(const std::string& name, std::string* error, const std::map<std::string, std::string>& metadata = {});
  /// Stops recording at once (the link is untapped) and finishes the file on a thread of its own
  /// (what is queued is written, then the summary and an fsync: seconds at worst, which must not
  /// hold the link's thread that answers this request); false when nothing records. Whether the
  /// file came out whole shows in state() once it is finished (dropped, error).
  bool stop(std::string* error);
  /// Waits until a stopped recording's file is finished; false with the reason when it is not
  /// whole (dropped messages or a write error — the file is still finished and readable).
  bool waitFinished(std::string* error);

  bool active() const;
  bool available() const { return !dir_.empty(); }
  link::proto::RecordingState state() const;

 private:
  link::LinkServer& server_;
  std::string dir_;
  record::LinkRecorderOptions options_;
  std::function<std::optional<link::proto::CalibrationInUse>()> calibration_source_;
  mutable std::mutex mutex_;
  std::shared_ptr<record::LinkRecorder> recorder_;   ///< recording now
  std::shared_ptr<record::LinkRecorder> finishing_;  ///< stopped, its file being finished
  struct Finisher {
    std::thread thread;
    std::shared_ptr<std::atomic<bool>> done = std::make_shared<std::atomic<bool>>(false);
  };
  /// One per stopped recording still being finished; the done ones are joined at the next stop,
  /// the rest by waitFinished (or at destruction).
  std::vector<Finisher> finishers_;
  link::proto::RecordingState last_;  ///< of the last finished recording
};

}  // namespace telesphere::robot::services
