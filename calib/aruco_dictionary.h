// SPDX-License-Identifier: MIT
/// @brief Internal to calib: ArUco dictionaries by name (OpenCV types stay out of public headers).
#pragma once

#include <opencv2/aruco.hpp>
#include <string>
#include <vector>

namespace telesphere::calib::detail {

/// The dictionary named `name`; throws std::invalid_argument for an unknown name.
cv::Ptr<cv::aruco::Dictionary> arucoDictionary(const std::string& name);
std::vector<std::string> arucoDictionaryNameList();

}  // namespace telesphere::calib::detail
