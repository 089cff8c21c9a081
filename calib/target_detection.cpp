// SPDX-License-Identifier: MIT
/// @brief Aprilgrid and ArUco detection with OpenCV's aruco module (see target_detection.h).
#include "calib/target_detection.h"

#include <map>
#include <opencv2/aruco.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "calib/aruco_dictionary.h"
#include "calib/marker_edge_corners.h"

namespace telesphere::calib {

namespace detail {

namespace {
const std::map<std::string, cv::aruco::PREDEFINED_DICTIONARY_NAME>& dictionaryTable() {
  static const std::map<std::string, cv::aruco::PREDEFINED_DICTIONARY_NAME> table = {
      {"DICT_4X4_50", cv::aruco::DICT_4X4_50},
      {"DICT_4X4_100", cv::aruco::DICT_4X4_100},
      {"DICT_5X5_100", cv::aruco::DICT_5X5_100},
      {"DICT_6X6_250", cv::aruco::DICT_6X6_250},
      {"DICT_ARUCO_ORIGINAL", cv::aruco::DICT_ARUCO_ORIGINAL},
      {"DICT_APRILTAG_36h11", cv::aruco::DICT_APRILTAG_36h11}};
  return table;
}
}  // namespace

cv::Ptr<cv::aruco::Dictionary> arucoDictionary(const std::string& name) {
  const auto it = dictionaryTable().find(name);
  if (it == dictionaryTable().end()) throw std::invalid_argument("unknown ArUco dictionary " + name);
  return cv::aruco::getPredefinedDictionary(it->second);
}

std::vector<std::string> arucoDictionaryNameList() {
  std::vector<std::string> names;
  for (const auto& [name, id] : dictionaryTable()) names.push_back(name);
  return names;
}

}  // namespace detail

namespace {

cv::Mat wrapGray(const GrayImage& image) {
  // OpenCV only reads it; the const_cast never leads to a write.
  return cv::Mat(image.height, image.width, CV_8UC1,
                 const_cast<std::uint8_t*>(image.pixels.data()));
}

cv::Ptr<cv::aruco::DetectorParameters> detectorParameters(int border_bits,
                                                          const DetectionOptions& options) {
  auto params = cv::aruco::DetectorParameters::create();
  params->markerBorderBits = border_bits;
  params->cornerRefinementMethod = cv::aruco::CORNER_REFINE_SUBPIX;
  params->cornerRefinementWinSize = options.subpixel_window_px;
  params->cornerRefinementMaxIterations = 50;
  params->cornerRefinementMinAccuracy = 0.005;
  return params;
}

bool insideMargin(const cv::Point2f& p, const GrayImage& image, double margin) {
  return p.x >= margin && p.y >= margin && p.x <= image.width - 1 - margin &&
         p.y <= image.height - 1 - margin;
}

}  // namespace

TargetObservation detectAprilGrid(const GrayImage& image, const AprilGrid& grid,
                                  const DetectionOptions& options) {
  TargetObservation out;
  if (image.width == 0 || image.height == 0) return out;
  std::vector<int> ids;
  std::vector<std::vector<cv::Point2f>> corners;
  cv::aruco::detectMarkers(wrapGray(image), detail::arucoDictionary("DICT_APRILTAG_36h11"),
                           corners, ids, detectorParameters(2, options));
  std::map<int, std::size_t> by_tag;  // sorted by tag; duplicates (misdetections) dropped
  std::vector<int> duplicate;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] < 0 || ids[i] >= grid.numTags()) continue;
    if (!by_tag.emplace(ids[i], i).second) duplicate.push_back(ids[i]);
  }
  for (int id : duplicate) by_tag.erase(id);
  out.tags_detected = static_cast<int>(by_tag.size());
  if (out.tags_detected < options.min_tags) return out;
  for (const auto& [tag, index] : by_tag) {
    for (int k = 0; k < 4; ++k) {
      const cv::Point2f& p = corners[index][static_cast<std::size_t>(kalibrToOpenCvCorner(k))];
      if (!insideMargin(p, image, options.border_margin_px)) continue;
      out.corner_ids.push_back(4 * tag + k);
      out.corners_px.emplace_back(p.x, p.y);
    }
  }
  return out;
}

std::vector<std::string> arucoDictionaryNames() { return detail::arucoDictionaryNameList(); }

std::optional<std::array<Eigen::Vector2d, 4>> detectArucoMarker(const GrayImage& image,
                                                                const std::string& dictionary,
                                                                int id,
                                                                const DetectionOptions& options) {
  const auto dict = detail::arucoDictionary(dictionary);
  if (image.width == 0 || image.height == 0) return std::nullopt;
  std::vector<int> ids;
  std::vector<std::vector<cv::Point2f>> corners;
  cv::aruco::detectMarkers(wrapGray(image), dict, corners, ids, detectorParameters(1, options));
  std::optional<std::array<Eigen::Vector2d, 4>> found;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] != id) continue;
    if (found) return std::nullopt;  // two markers with our id: ambiguous
    std::array<Eigen::Vector2d, 4> c;
    for (std::size_t j = 0; j < 4; ++j) {
      if (!insideMargin(corners[i][j], image, options.border_margin_px)) return std::nullopt;
      c[j] = Eigen::Vector2d(corners[i][j].x, corners[i][j].y);
    }
    found = c;
  }
  // cornerSubPix settles inside an L-shaped corner (marker_edge_corners.h); the sides' edges do not.
  if (found && options.marker_corners == MarkerCornerRefinement::kEdges) {
    if (const auto refined = refineMarkerCornersFromEdges(image, *found)) found = refined;
  }
  return found;
}

std::optional<GrayImage> readGrayImage(const std::string& path) {
  const cv::Mat mat = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (mat.empty() || mat.type() != CV_8UC1) return std::nullopt;
  GrayImage image(mat.cols, mat.rows);
  for (int v = 0; v < mat.rows; ++v)
    std::copy_n(mat.ptr<std::uint8_t>(v), mat.cols, &image.pixels[static_cast<std::size_t>(v) * mat.cols]);
  return image;
}

bool writeGrayImage(const GrayImage& image, const std::string& path) {
  try {
    return cv::imwrite(path, wrapGray(image));
  } catch (const cv::Exception&) {
    return false;
  }
}

}  // namespace telesphere::calib
