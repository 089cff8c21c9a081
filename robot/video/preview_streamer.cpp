// SPDX-License-Identifier: MIT
/// @brief PreviewStreamer: newest pair → box-filtered reduction → small JPEGs → link.
#include "robot/video/preview_streamer.h"

#include <algorithm>
#include <chrono>
#include <iostream>

#include "robot/cameras/debayer.h"
#include "robot/video/jpeg_encoder.h"

namespace telesphere::robot::video {

namespace {

/// A Bayer mosaic in blocks of an even size k: each block holds k²/4 red, k²/2 green and k²/4
/// blue samples, whose means are the preview pixel's colour (no demosaicing needed).
std::optional<PreviewImage> reduceBayerForPreview(const cameras::CameraFrame& frame, int k) {
  PreviewImage out;
  out.width = frame.width / k;
  out.height = frame.height / k;
  out.channels = 3;
  if (out.width < 1 || out.height < 1) return std::nullopt;
  out.pixels.resize(std::size_t(out.width) * std::size_t(out.height) * 3u);
  const std::uint32_t quarter = std::uint32_t(k) * std::uint32_t(k) / 4;  // red (blue) samples per block
  std::vector<std::uint32_t> sums(std::size_t(out.width) * 3u);
  for (int y = 0; y < out.height; ++y) {
    std::fill(sums.begin(), sums.end(), 0u);
    for (int dy = 0; dy < k; ++dy) {
      const int row_y = y * k + dy;
      const std::uint8_t* row = frame.pixels->data() + std::size_t(row_y) * std::size_t(frame.stride_bytes);
      for (int x = 0; x < out.width; ++x)
        for (int dx = 0; dx < k; ++dx) {
          const int column = x * k + dx;
          sums[std::size_t(x * 3 + cameras::bayerChannelAt(frame.format, column, row_y))] += row[column];
        }
    }
    std::uint8_t* dst = out.pixels.data() + std::size_t(y) * std::size_t(out.width) * 3u;
    for (int x = 0; x < out.width; ++x) {
      dst[3 * x] = std::uint8_t((sums[std::size_t(3 * x)] + quarter / 2) / quarter);
      dst[3 * x + 1] = std::uint8_t((sums[std::size_t(3 * x + 1)] + quarter) / (2 * quarter));
      dst[3 * x + 2] = std::uint8_t((sums[std::size_t(3 * x + 2)] + quarter / 2) / quarter);
    }
  }
  return out;
}

}  // namespace

std::optional<PreviewImage> reduceForPreview(const cameras::CameraFrame& frame, int max_width) {
  if (max_width < 1 || frame.width < 1 || frame.height < 1 || !frame.pixels) return std::nullopt;
  const int channels = cameras::bytesPerPixel(frame.format);
  if (frame.stride_bytes < frame.width * channels ||
      frame.pixels->size() < std::size_t(frame.stride_bytes) * std::size_t(frame.height - 1) +
                                 std::size_t(frame.width * channels))
    return std::nullopt;
  const int k = (frame.width + max_width - 1) / max_width;
  if (cameras::isBayer(frame.format)) return reduceBayerForPreview(frame, k + (k & 1));  // whole Bayer cells
  PreviewImage out;
  out.width = frame.width / k;
  out.height = frame.height / k;
  out.channels = channels;
  if (out.width < 1 || out.height < 1) return std::nullopt;
  out.pixels.resize(std::size_t(out.width) * std::size_t(out.height) * std::size_t(channels));
  const std::uint8_t* src = frame.pixels->data();
  const std::uint32_t n = std::uint32_t(k) * std::uint32_t(k);
  std::vector<std::uint32_t> sums(std::size_t(out.width) * std::size_t(channels));
  for (int y = 0; y < out.height; ++y) {
    std::fill(sums.begin(), sums.end(), 0u);
    for (int dy = 0; dy < k; ++dy) {
      const std::uint8_t* row = src + std::size_t(y * k + dy) * std::size_t(frame.stride_bytes);
      for (int x = 0; x < out.width; ++x)
        for (int dx = 0; dx < k; ++dx)
          for (int c = 0; c < channels; ++c)
            sums[std::size_t(x * channels + c)] += row[std::size_t(((x * k + dx) * channels) + c)];
    }
    std::uint8_t* dst = out.pixels.data() + std::size_t(y) * std::size_t(out.width * channels);
    for (std::size_t i = 0; i < sums.size(); ++i) dst[i] = std::uint8_t((sums[i] + n / 2) / n);
  }
  return out;
}

PreviewStreamer::PreviewStreamer(link::LinkServer& server, const PreviewOptions& options)
    : server_(server), options_(options) {}

PreviewStreamer::~PreviewStreamer() { stop(); }

void PreviewStreamer::start() {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this] { run(); });
}

void PreviewStreamer::stop() {
  {
    std::lock_guard lock(mutex_);
    running_ = false;
  }
  offered_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void PreviewStreamer::offer(const stereo::StereoFrame& pair, std::uint64_t sequence) {
  {
    std::lock_guard lock(mutex_);
    slot_.emplace(pair, sequence);
  }
  offered_.notify_one();
}

bool PreviewStreamer::publish(const stereo::StereoFrame& pair, std::uint64_t sequence, std::string* error) {
  JpegEncoder encoder;  // a handle per call: a few µs, and the thread keeps no encoder state
  JpegSettings settings;
  settings.quality = options_.quality;
  link::proto::PreviewFrame preview;
  preview.set_sequence(sequence);
  preview.set_capture_ns(std::min(pair.left.capture_ns, pair.right.capture_ns));
  preview.set_source_width(static_cast<std::uint32_t>(pair.left.width));
  preview.set_source_height(static_cast<std::uint32_t>(pair.left.height));
  link::SharedBytes jpegs[2];
  int index = 0;
  for (const cameras::CameraFrame* frame : {&pair.left, &pair.right}) {
    const auto image = reduceForPreview(*frame, options_.max_width);
    if (!image) {
      *error = std::string("cannot reduce a ") + cameras::pixelFormatName(frame->format) + " " +
               std::to_string(frame->width) + "x" + std::to_string(frame->height) + " image";
      return false;
    }
    auto jpeg = std::make_shared<std::vector<std::uint8_t>>();
    const bool ok = image->channels == 3
                        ? encoder.encodeRgb(image->pixels.data(), image->width, image->height,
                                            image->width * 3, settings, *jpeg, error)
                        : encoder.encodeGray(image->pixels.data(), image->width, image->height,
                                             image->width, settings, *jpeg, error);
    if (!ok) return false;
    preview.set_width(static_cast<std::uint32_t>(image->width));
    preview.set_height(static_cast<std::uint32_t>(image->height));
    jpegs[index++] = std::move(jpeg);
  }
  server_.publishPreview(std::move(preview), jpegs[0], jpegs[1]);
  ++published_;
  return true;
}

void PreviewStreamer::run() {
  const auto period = std::chrono::duration<double>(1.0 / options_.rate_hz);
  auto next = std::chrono::steady_clock::now();
  std::uint64_t failures = 0;
  while (true) {
    std::optional<std::pair<stereo::StereoFrame, std::uint64_t>> pair;
    {
      std::unique_lock lock(mutex_);
      offered_.wait(lock, [&] { return !running_ || slot_.has_value(); });
      if (!running_) return;
      pair = std::move(slot_);
      slot_.reset();
    }
    std::string error;
    if (!publish(pair->first, pair->second, &error) && failures++ % 100 == 0)
      std::cerr << "telesphere-robot: preview not sent: " << error << '\n';
    next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
    const auto now = std::chrono::steady_clock::now();
    if (next < now) next = now;
    std::unique_lock lock(mutex_);  // sleep until the next slot, waking at once on stop
    offered_.wait_until(lock, next, [&] { return !running_; });
    if (!running_) return;
  }
}

}  // namespace telesphere::robot::video
