// SPDX-License-Identifier: MIT
/// @brief RecordingPlayer (see recording_player.h).
#include "robot/record/recording_player.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/reflection.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <thread>

#include "robot/link/link_endpoints.h"

namespace telesphere::record {
namespace {

/// *_ns fields that are not robot-clock times: durations and the operator's clock.
const std::set<std::string>& notRobotClock() {
  static const std::set<std::string> names{"robot_to_xr_offset_ns", "round_trip_ns", "head_target_age_ns",
                                           "predicted_display_ns",  "display_ns",
                                           "client_send_ns",        "received_ns",  "decoded_ns",
                                           "uploaded_ns",           "displayed_ns"};
  return names;
}

bool endsWithNs(const std::string& name) { return name.size() > 3 && name.compare(name.size() - 3, 3, "_ns") == 0; }

}  // namespace

void shiftRobotClockStamps(google::protobuf::Message* message, std::int64_t shift_ns) {
  using google::protobuf::FieldDescriptor;
  const google::protobuf::Reflection* r = message->GetReflection();
  const google::protobuf::Descriptor* d = message->GetDescriptor();
  // In double: the stamps come from a file, their sums must not overflow.
  const auto shift = [&](std::int64_t t) {
    if (t == 0) return t;
    const double moved = double(t) + double(shift_ns);
    return std::abs(moved) < 9.2e18 ? static_cast<std::int64_t>(std::llround(moved)) : t;
  };
  for (int i = 0; i < d->field_count(); ++i) {
    const FieldDescriptor* f = d->field(i);
    if (f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
      if (f->is_repeated()) {
        for (int k = 0; k < r->FieldSize(*message, f); ++k) shiftRobotClockStamps(r->MutableRepeatedMessage(message, f, k), shift_ns);
      } else if (r->HasField(*message, f)) {
        shiftRobotClockStamps(r->MutableMessage(message, f), shift_ns);
      }
    } else if (f->cpp_type() == FieldDescriptor::CPPTYPE_INT64 && endsWithNs(f->name()) &&
               notRobotClock().count(f->name()) == 0) {
      if (f->is_repeated()) {
        for (int k = 0; k < r->FieldSize(*message, f); ++k)
          r->SetRepeatedInt64(message, f, k, shift(r->GetRepeatedInt64(*message, f, k)));
      } else {
        r->SetInt64(message, f, shift(r->GetInt64(*message, f)));
      }
    }
  }
}

std::optional<link::proto::CalibrationInUse> RecordingPlayer::calibrationNow() const {
  std::lock_guard lock(calibration_mutex_);
  return calibration_;
}

std::unique_ptr<RecordingPlayer> RecordingPlayer::open(const std::string& path, std::string* error) {
  auto session = RecordingReader::open(path, error);
  if (!session) return nullptr;
  std::unique_ptr<RecordingPlayer> replayer(new RecordingPlayer(std::move(session)));
  replayer->path_ = path;
  return replayer;
}

RecordingPlayerStats RecordingPlayer::stats() const {
  RecordingPlayerStats s;
  s.frames = session_->frames();
  s.states = states_;
  s.telemetry = telemetry_;
  s.health = health_;
  s.loops = loops_;
  s.skipped = session_->skipped() + not_replayed_;
  s.late_ms_max = late_ms_max_;
  return s;
}

bool RecordingPlayer::run(link::LinkServer& server, const RecordingPlayerOptions& options,
                          const std::atomic<bool>& stop, std::string* error) {
  const double rate = options.rate > 0 ? options.rate : 1.0;
  do {
    const auto wall_start = std::chrono::steady_clock::now();
    const std::int64_t start_ns = link::linkNowNs();
    std::optional<std::int64_t> first_ns;
    std::int64_t shift_ns = 0;  ///< of the message being replayed: its mapped log time minus its log time
    // A robot message parsed, its stamps moved, sent again with `publish` and counted.
    const auto republish = [&]<typename Message>(const McapMessageView& m,
                                                 void (link::LinkServer::*publish)(const Message&),
                                                 std::atomic<std::uint64_t>& count) {
      Message message;
      if (!message.ParseFromArray(m.data, static_cast<int>(m.size))) {
        ++not_replayed_;
        return true;
      }
      shiftRobotClockStamps(&message, shift_ns);
      (server.*publish)(message);
      ++count;
      return true;
    };
    RecordedSessionVisitor visitor;
    visitor.before = [&](std::int64_t t) {
      if (stop) return false;
      if (!first_ns) first_ns = t;
      // Due at the recorded pace; wait in slices so that a stop is heard. A log time before the
      // first is due at once.
      const double offset_ns = (double(t) - double(*first_ns)) / rate;
      const double shift = double(start_ns) + offset_ns - double(t);
      shift_ns = std::abs(shift) < 9.2e18 ? static_cast<std::int64_t>(std::llround(shift)) : 0;
      const auto due = wall_start + std::chrono::nanoseconds(std::llround(std::max(0.0, offset_ns)));
      while (!stop && std::chrono::steady_clock::now() < due)
        std::this_thread::sleep_until(std::min(due, std::chrono::steady_clock::now() + std::chrono::milliseconds(50)));
      if (stop) return false;
      const double late_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - due).count();
      if (late_ms > late_ms_max_) late_ms_max_ = late_ms;
      return true;
    };
    visitor.calibration = [&](const RecordedCalibration& c) {
      link::proto::CalibrationInUse in_use;
      in_use.set_generation(c.generation);
      in_use.set_yaml(c.yaml);
      in_use.set_source("recording " + path_ + ", generation " + std::to_string(c.generation));
      std::lock_guard lock(calibration_mutex_);
      calibration_ = std::move(in_use);
      return true;
    };
    visitor.frame = [&](RecordedFrame&& frame) {
      shiftRobotClockStamps(&frame.frame, shift_ns);
      server.publishStereoFrame(std::move(frame.frame), std::move(frame.left), std::move(frame.right));
      return true;
    };
    visitor.message = [&](RecordedTopic topic, const McapMessageView& m) {
      switch (topic) {
        case RecordedTopic::kRobotState: return republish(m, &link::LinkServer::publishRobotState, states_);
        case RecordedTopic::kRobotTelemetry: return republish(m, &link::LinkServer::publishTelemetry, telemetry_);
        case RecordedTopic::kRobotHealth: return republish(m, &link::LinkServer::publishHealth, health_);
        default: ++not_replayed_; return true;  // what clients sent the robot
      }
    };
    if (!session_->forEach(visitor, error)) return false;
    if (!stop) ++loops_;
  } while (options.loop && !stop);
  return true;
}

}  // namespace telesphere::record
