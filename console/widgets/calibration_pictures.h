// SPDX-License-Identifier: MIT
/// @brief The Calibration panel's pictures: a stereo still or sample with its corners drawn
///        (the sample list's thumbnails, the live view) and the polar-bin coverage of both
///        cameras against the done rule.
#pragma once

#include <QImage>
#include <QPixmap>

#include "console/calibration/intrinsics_collector.h"
#include "console/calibration/intrinsics_done_rule.h"
#include "console/calibration/live_capture.h"
#include "console/calibration/stereo_sample.h"

namespace telesphere::console {

/// A sample's two thumbnails with its corners (the sample list).
QImage sampleImage(const calibration::StereoSample& s);

/// A live still: the corners green when the gates pass and orange when not, each camera's
/// corner count.
QImage liveImage(const calibration::LiveStill& still);

/// The polar bins of both cameras as rows of cells: reached (green), required and missing (red),
/// optional (grey); the bin edges in degrees underneath.
QPixmap coveragePicture(const calibration::IntrinsicsCollector& collector, const calibration::IntrinsicsDoneRule& rule);

}  // namespace telesphere::console
