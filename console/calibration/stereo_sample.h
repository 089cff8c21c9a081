// SPDX-License-Identifier: MIT
/// @brief One calibration sample from a stereo still (issue #15): the Aprilgrid's corners in
///        each camera at full resolution, the capture time and the head joints at that time, and
///        a small thumbnail of each image for the sample list.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "calib/aprilgrid.h"
#include "calib/gray_image.h"
#include "calib/target_detection.h"
#include "robot/link/telesphere_link.pb.h"

namespace telesphere::console::calibration {

struct StereoSample {
  std::uint64_t sequence = 0;     ///< the stereo frame's sequence on the link
  std::int64_t capture_ns = 0;    ///< robot clock
  std::vector<double> head_joints;  ///< rad, at capture_ns
  std::array<calib::TargetObservation, 2> views;  ///< [0] cam_l, [1] cam_r
  std::array<calib::GrayImage, 2> thumbnails;     ///< ≤ 160 px wide (detectStereoSample's default)
  int width = 0, height = 0;      ///< full resolution of the images
};

/// The still's image as a GrayImage; empty (0×0) when the sizes do not match the bytes.
calib::GrayImage grayImageOf(const link::proto::CalibrationImage& image);

/// A box-filtered copy at most `max_width` wide.
calib::GrayImage thumbnailOf(const calib::GrayImage& image, int max_width = 160);

/// Detects the grid in both images of `still`; the thumbnails at most `thumbnail_width` wide.
StereoSample detectStereoSample(const link::proto::CalibrationStill& still, const calib::AprilGrid& grid,
                                const calib::DetectionOptions& options = {}, int thumbnail_width = 160);

}  // namespace telesphere::console::calibration
