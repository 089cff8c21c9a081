// SPDX-License-Identifier: MIT
/// @brief RecordingSwitch (see recording_switch.h).
#include "robot/services/recording_switch.h"

#include <filesystem>

#include "robot/link/link_endpoints.h"

namespace telesphere::robot::services {

RecordingSwitch::RecordingSwitch(link::LinkServer& server, std::string dir, record::LinkRecorderOptions options)
    : server_(server), dir_(std::move(dir)), options_(options) {}

RecordingSwitch::~RecordingSwitch() {
  std::string ignored;
  if (active()) stop(&ignored);
  waitFinished(&ignored);
}

void RecordingSwitch::setCalibrationSource(std::function<std::optional<link::proto::CalibrationInUse>()> source) {
  std::lock_guard lock(mutex_);
  calibration_source_ = std::move(source);
}

bool RecordingSwitch::startFile(const std::string& path, std::string* error,
                                 const std::map<std::string, std::string>& metadata) {
  std::lock_guard lock(mutex_);
  if (recorder_) {
    *error = "already recording to " + recorder_->path();
    return false;
  }
  record::LinkRecorderOptions options = options_;
  for (const auto& [key, value] : metadata) options.metadata[key] = value;
  auto recorder = record::LinkRecorder::start(path, options, error);
  if (!recorder) return false;
  recorder_ = std::move(recorder);
  // The calibration in use from the first moment: a replay renders each frame with its own.
  if (calibration_source_)
    if (const auto calibration = calibration_source_()) recorder_->attachCalibration(*calibration, link::linkNowNs());
  server_.setTap(recorder_);
  return true;
}

bool RecordingSwitch::startNamed(const std::string& name, std::string* error,
                                  const std::map<std::string, std::string>& metadata) {
  if (dir_.empty()) {
    *error = "this robot records only with a record folder (telesphere-robot --record-dir DIR)";
    return false;
  }
  if (name.size() > 200) {
    *error = "recording name of " + std::to_string(name.size()) + " characters: at most 200";
    return false;
  }
  const bool plain = !name.empty() && name.front() != '.' &&
                     name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_.") ==
                         std::string::npos;
  if (!plain) {
    *error = "recording name '" + name + "' is not a plain file name (letters, digits, - _ .)";
    return false;
  }
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) {
    *error = "cannot create the record folder " + dir_ + ": " + ec.message();
    return false;
  }
  const bool has_suffix = name.size() > 5 && name.compare(name.size() - 5, 5, ".mcap") == 0;
  return startFile((std::filesystem::path(dir_) / (has_suffix ? name : name + ".mcap")).string(), error, metadata);
}

bool RecordingSwitch::stop(std::string* error) {
  std::lock_guard lock(mutex_);
  if (!recorder_) {
    *error = "not recording";
    return false;
  }
  server_.setTap(nullptr);  // under the lock: a start right after cannot lose its tap to this stop
  finishing_ = std::move(recorder_);
  // Threads of earlier stops that have finished are joined here (at once: they only return), so
  // a robot that records many times does not keep one thread per stop.
  std::erase_if(finishers_, [](Finisher& f) {
    if (!f.done->load()) return false;
    f.thread.join();
    return true;
  });
  Finisher& finisher = finishers_.emplace_back();
  finisher.thread = std::thread([this, recorder = finishing_, done = finisher.done] {
    recorder->stop();
    const auto stats = recorder->stats();
    {
      std::lock_guard lock(mutex_);
      last_.Clear();
      last_.set_file(recorder->path());
      last_.set_messages(stats.messages);
      last_.set_bytes(stats.file_bytes);
      last_.set_dropped(stats.dropped);
      last_.set_error(stats.error);
      if (finishing_ == recorder) finishing_.reset();
    }
    done->store(true);  // after the lock: a stop joining this thread waits for nothing held
  });
  return true;
}

bool RecordingSwitch::waitFinished(std::string* error) {
  std::vector<Finisher> finishers;
  {
    std::lock_guard lock(mutex_);
    finishers.swap(finishers_);
  }
  for (Finisher& f : finishers) f.thread.join();
  std::lock_guard lock(mutex_);
  if (last_.dropped() == 0 && last_.error().empty()) return true;
  *error = last_.file() + " is not whole: " +
           (last_.error().empty() ? std::to_string(last_.dropped()) + " messages dropped" : last_.error());
  return false;
}

bool RecordingSwitch::active() const {
  std::lock_guard lock(mutex_);
  return recorder_ != nullptr;
}

link::proto::RecordingState RecordingSwitch::state() const {
  std::lock_guard lock(mutex_);
  link::proto::RecordingState s;
  // Recording, or stopped and still being finished: that file's figures as they stand.
  if (const auto& r = recorder_ ? recorder_ : finishing_) {
    const auto stats = r->stats();
    s.set_active(recorder_ != nullptr);
    s.set_file(r->path());
    s.set_messages(stats.messages);
    s.set_bytes(stats.file_bytes);
    s.set_dropped(stats.dropped);
    s.set_error(stats.error);
  } else {
    s = last_;
  }
  s.set_available(!dir_.empty());
  return s;
}

}  // namespace telesphere::robot::services
