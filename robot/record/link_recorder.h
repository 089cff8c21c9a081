// SPDX-License-Identifier: MIT
/// @brief Records a session: everything that crosses the link (a link::LinkTap on the robot's
///        LinkServer) into an MCAP file, on its own thread, never slowing the link.
///
///   link threads ──onLinkMessage──▶ bounded queue ──writer thread──▶ McapWriter ──▶ FILE.mcap
///
/// The link's threads only copy the (small) message body and keep a reference to the JPEGs; the
/// writer thread encodes, chunks and writes. When the disk cannot keep up the queue fills to
/// `max_queue_bytes` and further messages are dropped and counted (stats().dropped), never
/// waited for; a write error ends the recording (stats().error) and counts the rest as dropped.
/// Topics and schemas: recording_topics.h. Log times are UTC (the steady clock plus an offset
/// taken at the start and written in the "telesphere" metadata record, with `metadata`: which
/// robot, which software, which study trial); the calibration in use is attached at the start
/// (attachCalibration) and whenever a control reply carries a new generation (apply, revert);
/// camera and head poses also go out as foxglove.FrameTransform on /tf.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <thread>

#include "robot/link/link_tap.h"
#include "robot/record/mcap_writer.h"
#include "robot/record/recording_topics.h"

namespace telesphere::record {

struct LinkRecorderOptions {
  McapWriterOptions mcap;
  /// Into the "telesphere" metadata record beside the clock offset ("robot", "arm", "cameras",
  /// a study trial's "participant", "trial_id", …).
  std::map<std::string, std::string> metadata;
  std::size_t max_queue_bytes = std::size_t(512) << 20;  ///< about 15 s of the paper's 30 MB/s
};

struct LinkRecorderStats {
  std::uint64_t messages = 0;        ///< written to the file
  std::uint64_t stereo_frames = 0;   ///< of them, stereo frames (three messages each)
  std::uint64_t dropped = 0;         ///< messages lost: queue full or the file failed
  std::uint64_t attachments = 0;     ///< calibrations attached
  std::uint64_t payload_bytes = 0;   ///< message bytes written
  std::uint64_t file_bytes = 0;      ///< the file's size so far
  std::size_t queue_bytes_max = 0;   ///< the queue's high-water mark
  std::string error;                 ///< why recording stopped early (empty: it did not)
};

class LinkRecorder final : public link::LinkTap {
 public:
  /// Creates `path`, writes the schemas and channels, starts the writer thread; null with the
  /// reason. Give it to LinkServer::setTap to record.
  static std::shared_ptr<LinkRecorder> start(const std::string& path, const LinkRecorderOptions& options,
                                                std::string* error);
  ~LinkRecorder() override;

  void onLinkMessage(Direction direction, const link::proto::Envelope& envelope,
                     const std::shared_ptr<const std::vector<std::uint8_t>>& left_jpeg,
                     const std::shared_ptr<const std::vector<std::uint8_t>>& right_jpeg) override;

  /// Attaches the calibration in use (our YAML) at steady time t_ns, once per generation.
  void attachCalibration(const link::proto::CalibrationInUse& calibration, std::int64_t t_ns);
  /// t_utc_ns = t_steady_ns + this (the recording's log times are UTC).
  std::int64_t steadyToUtcOffsetNs() const { return steady_to_utc_ns_; }

  /// Writes what is queued, finishes the file (summary, footer) and stops; later messages are
  /// ignored. True when the whole recording is in the file. Idempotent.
  bool stop();

  LinkRecorderStats stats() const;
  const std::string& path() const { return path_; }

 private:
  struct Item {
    bool attachment = false;  ///< a calibration to attach (name, media type, body)
    std::string name;
    RecordedTopic topic;
    std::uint64_t log_time_ns, publish_time_ns;
    std::uint32_t sequence;
    std::string body;  ///< the serialized message (for a stereo frame: its StereoFrame)
    std::int64_t capture_ns[2] = {0, 0};
    std::shared_ptr<const std::vector<std::uint8_t>> jpeg[2];
    std::vector<std::string> transforms;  ///< foxglove.FrameTransform bodies for /tf
    std::size_t bytes() const;
  };
  LinkRecorder(std::string path, std::unique_ptr<McapWriter> writer, std::size_t max_queue_bytes);
  void run();
  void writeItem(const Item& item);
  bool enqueue(Item&& item, std::uint64_t messages);  ///< false: dropped (counted)

  std::string path_;
  std::unique_ptr<McapWriter> writer_;
  std::uint16_t channel_[static_cast<int>(RecordedTopic::kCount)] = {};
  std::int64_t steady_to_utc_ns_ = 0;
  std::set<std::uint64_t> calibrations_attached_;  ///< generations (under mutex_)
  std::size_t max_queue_bytes_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Item> queue_;
  std::size_t queue_bytes_ = 0;
  bool stopping_ = false, stopped_ = false;
  LinkRecorderStats stats_;
  std::thread thread_;
};

}  // namespace telesphere::record
