// SPDX-License-Identifier: MIT
/// @brief views.csv (xr/frame_loop/logged_view.h): rows appended one at a time read back with the
///        exact poses (17 digits), a header written once, and every kind of bad file refused with
///        its line: foreign header, wrong field count, a path for a file name, a negative or
///        non-numeric sequence, a non-finite number, a quaternion far from unit length, an empty file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <unistd.h>

#include "xr/frame_loop/logged_view.h"

namespace telesphere::xr {
namespace {

namespace fs = std::filesystem;

class LoggedViewTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("telesphere-logged-view-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  fs::path dir_;
};

TEST_F(LoggedViewTest, RowsAppendedReadBackWithTheExactPoses) {
  const std::string path = (dir_ / "views.csv").string();
  std::mt19937 rng(20261127);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<frame_loop::LoggedView> written;
  for (int i = 0; i < 50; ++i) {
    frame_loop::LoggedView v;
    v.png = "eyes_" + std::to_string(10 * (i + 1)) + ".png";
    v.stereo_sequence = i == 49 ? std::uint64_t(18446744073709551615ull) : std::uint64_t(3 * i);
    const Eigen::Quaterniond q = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
    v.T_vr_hmd.linear() = q.toRotationMatrix();
    v.T_vr_hmd.translation() = Eigen::Vector3d(u(rng), 1.6 + u(rng), 1e-9 * u(rng));
    v.image_saturation = i % 3 == 0 ? 0.0f : 1.0f;
    v.link_state.image_age_ms = 1000.0 * (1.0 + u(rng));
    v.link_state.eye_camera_distance_m = i % 5 == 0 ? -1.0 : 0.1 * (1.0 + u(rng));
    v.link_state.stream_text = i % 2 == 0 ? "" : "LINK 8.5M 15HZ 50% Q70";
    v.link_state.insecure = i % 7 == 0;
    std::string error;
    ASSERT_TRUE(frame_loop::appendLoggedView(path, v, &error)) << error;
    written.push_back(v);
  }
  std::string error;
  const auto read = frame_loop::loadLoggedViews(path, &error);
  ASSERT_TRUE(read) << error;
  ASSERT_EQ(read->size(), written.size());
  for (std::size_t i = 0; i < written.size(); ++i) {
    EXPECT_EQ((*read)[i].png, written[i].png);
    EXPECT_EQ((*read)[i].stereo_sequence, written[i].stereo_sequence);
    EXPECT_EQ((*read)[i].T_vr_hmd.translation(), written[i].T_vr_hmd.translation()) << "row " << i;
    // The rotation goes through a quaternion: equal to the last bits, not bit for bit.
    EXPECT_LT(((*read)[i].T_vr_hmd.linear() - written[i].T_vr_hmd.linear()).cwiseAbs().maxCoeff(), 1e-15) << "row " << i;
    // The link's cues over the PNG, exactly (the replay draws them again).
    EXPECT_EQ((*read)[i].image_saturation, written[i].image_saturation);
    EXPECT_EQ((*read)[i].link_state.image_age_ms, written[i].link_state.image_age_ms);
    EXPECT_EQ((*read)[i].link_state.eye_camera_distance_m, written[i].link_state.eye_camera_distance_m);
    EXPECT_EQ((*read)[i].link_state.stream_text, written[i].link_state.stream_text);
    EXPECT_EQ((*read)[i].link_state.insecure, written[i].link_state.insecure) << "row " << i;
  }
  std::ifstream in(path);
  std::string first;
  std::getline(in, first);
  EXPECT_EQ(first,
            "png,stereo_sequence,px,py,pz,qx,qy,qz,qw,image_saturation,link_age_ms,eye_camera_distance_m,stream_text,"
            "insecure_link");
}

TEST_F(LoggedViewTest, FilesWrittenBeforeTheInsecureColumnStillLoad) {
  const std::string path =
      write("cues.csv",
            "png,stereo_sequence,px,py,pz,qx,qy,qz,qw,image_saturation,link_age_ms,eye_camera_distance_m,stream_text\n"
            "eyes_00010.png,7,0,1.6,0,0,0,0,1,1,300,-1,\n");
  std::string error;
  const auto read = frame_loop::loadLoggedViews(path, &error);
  ASSERT_TRUE(read) << error;
  ASSERT_EQ(read->size(), 1u);
  EXPECT_EQ((*read)[0].link_state.image_age_ms, 300.0);
  EXPECT_FALSE((*read)[0].link_state.insecure);
  const std::string bad = write(
      "bad_insecure.csv",
      "png,stereo_sequence,px,py,pz,qx,qy,qz,qw,image_saturation,link_age_ms,eye_camera_distance_m,stream_text,"
      "insecure_link\neyes_00010.png,7,0,1.6,0,0,0,0,1,1,300,-1,,yes\n");
  EXPECT_FALSE(frame_loop::loadLoggedViews(bad, &error));
  EXPECT_NE(error.find("insecure_link 'yes'"), std::string::npos) << error;
}

TEST_F(LoggedViewTest, FilesWrittenBeforeTheCuesStillLoad) {
  const std::string path = write("old.csv", "png,stereo_sequence,px,py,pz,qx,qy,qz,qw\neyes_00010.png,7,0,1.6,0,0,0,0,1\n");
  std::string error;
  const auto read = frame_loop::loadLoggedViews(path, &error);
  ASSERT_TRUE(read) << error;
  ASSERT_EQ(read->size(), 1u);
  EXPECT_EQ((*read)[0].image_saturation, 1.0f);
  EXPECT_LT((*read)[0].link_state.image_age_ms, 0.0) << "no cues";
}

TEST_F(LoggedViewTest, BadFilesAreRefusedWithTheirLine) {
  const std::string header = "png,stereo_sequence,px,py,pz,qx,qy,qz,qw\n";
  const std::string good = "eyes_00010.png,7,0,1.6,0,0,0,0,1\n";
  struct Case {
    std::string text, expected;
  };
  const Case cases[] = {
      {"t,px,py,pz,qx,qy,qz,qw\n" + good, ":1: not a views file"},
      {"png,stereo_sequence,px,py,pz,qx,qy,qz,qw,image_saturation,link_age_ms,eye_camera_distance_m,stream_text\n"
       "eyes_1.png,7,0,1.6,0,0,0,0,1,2,300,-1,\n", ":2: image_saturation outside [0, 1]"},
      {"png,stereo_sequence,px,py,pz,qx,qy,qz,qw,image_saturation,link_age_ms,eye_camera_distance_m,stream_text\n"
       "eyes_1.png,7,0,1.6,0,0,0,0,1,1,x,-1,\n", ":2: 'x' is not a finite number"},
      {header + good + "eyes_1.png,7,0,1.6,0,0,0,1\n", ":3: 9 fields expected, 8 found"},
      {header + "../eyes_1.png,7,0,1.6,0,0,0,0,1\n", ":2: '../eyes_1.png' is not a file name"},
      {header + ",7,0,1.6,0,0,0,0,1\n", ":2: '' is not a file name"},
      {header + "eyes_1.png,-7,0,1.6,0,0,0,0,1\n", ":2: stereo_sequence '-7' is not a number"},
      {header + "eyes_1.png,7x,0,1.6,0,0,0,0,1\n", ":2: stereo_sequence '7x' is not a number"},
      {header + "eyes_1.png,99999999999999999999999,0,1.6,0,0,0,0,1\n", ":2: stereo_sequence"},
      {header + "eyes_1.png,7,nan,1.6,0,0,0,0,1\n", ":2: 'nan' is not a finite number"},
      {header + "eyes_1.png,7,0,1e999,0,0,0,0,1\n", ":2: '1e999' is not a finite number"},
      {header + "eyes_1.png,7,0,1.6,0,0,0,0,2\n", ":2: the quaternion is not of unit length"},
      {header + "eyes_1.png,7,0,1.6,0,0,0,0,0\n", ":2: the quaternion is not of unit length"},
      {"", "empty (not a views file)"},
  };
  int i = 0;
  for (const Case& c : cases) {
    const std::string path = write("bad" + std::to_string(i++) + ".csv", c.text);
    std::string error;
    EXPECT_FALSE(frame_loop::loadLoggedViews(path, &error)) << c.text;
    EXPECT_NE(error.find(c.expected), std::string::npos) << "got: " << error << "\nexpected: " << c.expected;
    EXPECT_NE(error.find(path), std::string::npos) << error;
  }
  std::string error;
  EXPECT_FALSE(frame_loop::loadLoggedViews((dir_ / "absent.csv").string(), &error));
  EXPECT_NE(error.find("cannot open"), std::string::npos) << error;
  // A header alone is a file without views (the live run wrote no PNG): read, empty.
  const auto none = frame_loop::loadLoggedViews(write("none.csv", header), &error);
  ASSERT_TRUE(none) << error;
  EXPECT_TRUE(none->empty());
}

TEST_F(LoggedViewTest, AnUnwritableFileSaysWhy) {
  std::string error;
  EXPECT_FALSE(frame_loop::appendLoggedView((dir_ / "no-such-dir" / "views.csv").string(), frame_loop::LoggedView{}, &error));
  EXPECT_NE(error.find("no-such-dir"), std::string::npos) << error;
}

}  // namespace
}  // namespace telesphere::xr
