// SPDX-License-Identifier: MIT
/// @brief A telesphere recording read back as the robot sent it, message by message in file
///        order: a stereo frame's three messages (its StereoFrame and the left and right JPEG,
///        joined by their shared sequence) handed on as one frame, every other message with its
///        topic. What RecordingPlayer serves on the link (`telesphere-robot --replay`) and what
///        the operator app renders offline (`telesphere-xr offscreen --replay`). Times are handed
///        on in the robot's steady clock: a recording logged on UTC names its offset in its
///        "telesphere" metadata, which is taken off again (older recordings logged steady times).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "robot/link/telesphere_link.pb.h"
#include "robot/record/mcap_reader.h"
#include "robot/record/recording_topics.h"

namespace telesphere::record {

/// A calibration the robot used, as the recording attached it (at the start and at each change).
struct RecordedCalibration {
  std::uint64_t generation = 0;
  std::int64_t log_time_ns = 0;  ///< the robot's steady clock
  std::string yaml;              ///< our format (a comment line first says its source)
};

/// One stereo frame as sent: its message and both JPEGs.
struct RecordedFrame {
  std::int64_t log_time_ns = 0;  ///< the robot's steady clock when it was sent
  link::proto::StereoFrame frame;
  std::shared_ptr<const std::vector<std::uint8_t>> left, right;
};

/// What a walk over the recording calls; each returns false to stop the walk (not an error).
struct RecordedSessionVisitor {
  /// Before every message, with its log time (ns, the robot's steady clock); may be empty.
  std::function<bool(std::int64_t log_time_ns)> before;
  /// A stereo frame both of whose images were recorded; may be empty.
  std::function<bool(RecordedFrame&& frame)> frame;
  /// Every other message of a recorded topic (data valid during the call); may be empty.
  std::function<bool(RecordedTopic topic, const McapMessageView& message)> message;
  /// A calibration attachment, in file order (before the frames that use it); may be empty.
  std::function<bool(const RecordedCalibration& calibration)> calibration;
};

class RecordingReader {
 public:
  /// Maps `path` and checks that it is a telesphere recording (its summary, or a scan when it
  /// has none, names /stereo/frame); null with the reason.
  static std::unique_ptr<RecordingReader> open(const std::string& path, std::string* error);

  /// One pass over every message in file order. False with the reason when the file is damaged
  /// part way (what came before was handed on) or a message is logged over a day after the
  /// first (a corrupt time that would stall a paced replay).
  bool forEach(const RecordedSessionVisitor& visitor, std::string* error) const;

  /// The calibration attached before the first message (the one in use when recording began),
  /// or nothing (a recording from before calibrations were attached).
  std::optional<RecordedCalibration> firstCalibration() const;

  const McapSummary& summary() const { return summary_; }
  /// Over all passes so far: frames handed on; messages passed over (unknown topics, images
  /// without their frame, frames missing an image, bodies that do not parse, over 2 GiB).
  std::uint64_t frames() const { return frames_; }
  std::uint64_t skipped() const { return skipped_; }

 private:
  explicit RecordingReader(std::unique_ptr<McapReader> reader) : reader_(std::move(reader)) {}
  std::unique_ptr<McapReader> reader_;
  McapSummary summary_;
  mutable std::atomic<std::uint64_t> frames_{0}, skipped_{0};
};

}  // namespace telesphere::record
