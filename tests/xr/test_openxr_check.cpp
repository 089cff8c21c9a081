// SPDX-License-Identifier: MIT
/// @brief Checked OpenXR calls: result names from the reflection header, failure messages with
///        the call's text and place, qualified successes, and the swapchain format choice.
#include <gtest/gtest.h>

#include "xr/openxr/openxr_check.h"
#include "xr/openxr/openxr_swapchain_format.h"

namespace telesphere::xr {
namespace {

XrResult openXrCheckTestReturn(XrResult r) { return r; }

TEST(OpenXrCheck, ResultNamesComeFromTheRegistry) {
  EXPECT_EQ(openxr::xrResultName(XR_SUCCESS), "XR_SUCCESS");
  EXPECT_EQ(openxr::xrResultName(XR_ERROR_SESSION_LOST), "XR_ERROR_SESSION_LOST");
  EXPECT_EQ(openxr::xrResultName(XR_ERROR_RUNTIME_UNAVAILABLE), "XR_ERROR_RUNTIME_UNAVAILABLE");
  EXPECT_EQ(openxr::xrResultName(XR_SESSION_LOSS_PENDING), "XR_SESSION_LOSS_PENDING");
  EXPECT_EQ(openxr::xrResultName(XrResult(-987654)), "XrResult(-987654)");
}

TEST(OpenXrCheck, FailureNamesTheCallTheResultAndThePlace) {
  std::string error;
  XrResult result = XR_SUCCESS;
  const int line = __LINE__ + 1;
  const bool ok = TELESPHERE_CHECK_XR_RESULT(openXrCheckTestReturn(XR_ERROR_SESSION_NOT_RUNNING), &error, &result);
  EXPECT_FALSE(ok);
  EXPECT_EQ(result, XR_ERROR_SESSION_NOT_RUNNING);
  EXPECT_NE(error.find("openXrCheckTestReturn(XR_ERROR_SESSION_NOT_RUNNING) failed: "
                       "XR_ERROR_SESSION_NOT_RUNNING (-16)"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("test_openxr_check.cpp:" + std::to_string(line) + "]"), std::string::npos) << error;
}

TEST(OpenXrCheck, SuccessesIncludingQualifiedOnesPassAndLeaveTheErrorAlone) {
  std::string error = "untouched";
  EXPECT_TRUE(TELESPHERE_CHECK_XR(openXrCheckTestReturn(XR_SUCCESS), &error));
  EXPECT_TRUE(TELESPHERE_CHECK_XR(openXrCheckTestReturn(XR_SESSION_LOSS_PENDING), &error));
  EXPECT_TRUE(TELESPHERE_CHECK_XR(openXrCheckTestReturn(XR_EVENT_UNAVAILABLE), &error));
  EXPECT_EQ(error, "untouched");
  EXPECT_FALSE(TELESPHERE_CHECK_XR(openXrCheckTestReturn(XR_ERROR_VALIDATION_FAILURE), nullptr))
      << "a null error out-parameter is allowed";
}

// GL internal formats as a runtime lists them.
constexpr std::int64_t kTestRgba8 = 0x8058, kTestSrgb8Alpha8 = 0x8C43, kTestRgba16f = 0x881A,
                       kTestRgb10A2 = 0x8059, kTestDepth32f = 0x8CAC, kTestSrgb8 = 0x8C41;

TEST(OpenXrSwapchainFormat, SrgbIsPreferredEvenWhenListedAfterLinearFormats) {
  const auto c = openxr::chooseSwapchainFormat({kTestRgba16f, kTestRgba8, kTestSrgb8Alpha8, kTestDepth32f},
                                       openxr::SwapchainColour::kAuto);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->format, kTestSrgb8Alpha8);
  EXPECT_TRUE(c->srgb);
}

TEST(OpenXrSwapchainFormat, TheRuntimesOrderDecidesWithinAKind) {
  const auto c = openxr::chooseSwapchainFormat({kTestSrgb8, kTestSrgb8Alpha8}, openxr::SwapchainColour::kSrgb);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->format, kTestSrgb8);
  const auto l = openxr::chooseSwapchainFormat({kTestRgb10A2, kTestRgba8, kTestSrgb8Alpha8}, openxr::SwapchainColour::kLinear);
  ASSERT_TRUE(l);
  EXPECT_EQ(l->format, kTestRgb10A2);
  EXPECT_FALSE(l->srgb);
}

TEST(OpenXrSwapchainFormat, FallsBackToTheOtherKindAndRefusesUnusableLists) {
  const auto linear_only = openxr::chooseSwapchainFormat({kTestDepth32f, kTestRgba8}, openxr::SwapchainColour::kSrgb);
  ASSERT_TRUE(linear_only);
  EXPECT_EQ(linear_only->format, kTestRgba8);
  EXPECT_FALSE(linear_only->srgb);
  const auto srgb_only = openxr::chooseSwapchainFormat({kTestSrgb8Alpha8}, openxr::SwapchainColour::kLinear);
  ASSERT_TRUE(srgb_only);
  EXPECT_TRUE(srgb_only->srgb);
  EXPECT_FALSE(openxr::chooseSwapchainFormat({kTestDepth32f}, openxr::SwapchainColour::kAuto));
  EXPECT_FALSE(openxr::chooseSwapchainFormat({}, openxr::SwapchainColour::kAuto));
}

TEST(OpenXrSwapchainFormat, FormatNames) {
  EXPECT_EQ(openxr::glFormatName(kTestSrgb8Alpha8), "GL_SRGB8_ALPHA8");
  EXPECT_EQ(openxr::glFormatName(kTestRgba16f), "GL_RGBA16F");
  EXPECT_EQ(openxr::glFormatName(kTestDepth32f), "0x8cac");
}

}  // namespace
}  // namespace telesphere::xr
