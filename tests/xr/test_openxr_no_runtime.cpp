// SPDX-License-Identifier: MIT
/// @brief `telesphere-xr openxr` on a machine without an OpenXR runtime (as this one is without
///        tests/xr/monado): one clear message that says how to get a runtime and how to run
///        without a headset, and exit code 5.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace telesphere::test {
namespace {

TEST(OpenXrNoRuntime, SaysHowToGetARuntimeAndHowToRunWithoutAHeadset) {
  // A runtime manifest that does not exist: the loader finds no runtime.
  const std::string command =
      "env XR_RUNTIME_JSON=/nonexistent/telesphere-no-runtime.json XDG_CONFIG_DIRS=/nonexistent "
      "XDG_CONFIG_HOME=/nonexistent '" TELESPHERE_BINARY_DIR "/bin/telesphere-xr' openxr --test-scene --frames 1 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, n);
  const int status = pclose(pipe);
  ASSERT_TRUE(WIFEXITED(status)) << output;
  EXPECT_EQ(WEXITSTATUS(status), 5) << output;
  EXPECT_NE(output.find("no OpenXR runtime is available"), std::string::npos) << output;
  EXPECT_NE(output.find("Monado"), std::string::npos) << output;
  EXPECT_NE(output.find("SteamVR"), std::string::npos) << output;
  EXPECT_NE(output.find("Without a headset"), std::string::npos) << output;
  EXPECT_EQ(output.find("frames: requested"), std::string::npos) << "only the one message\n" << output;
  EXPECT_EQ(output.find("AddressSanitizer"), std::string::npos) << output;
}

}  // namespace
}  // namespace telesphere::test
