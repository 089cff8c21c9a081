// SPDX-License-Identifier: MIT
/// @brief The link's visual-mode, depth-proxy and chroma enums: names round trip, the operator's mode
///        and proxy cycles visit all three, every value maps to its proto value and back, and what the
///        proto may carry that we do not know (UNSPECIFIED, a newer peer's value) maps to nothing;
///        the sphere radius range at and beyond its ends.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

#include "robot/link/proto_enums.h"
#include "robot/link/sphere_radius.h"

namespace telesphere::link {
namespace {

TEST(LinkEnums, VisualModeNamesCycleAndProtoRoundTrip) {
  std::set<std::string_view> names;
  VisualMode m = VisualMode::kFull6d;
  for (int i = 0; i < 3; ++i) {
    names.insert(visualModeName(m));
    EXPECT_EQ(parseVisualMode(visualModeName(m)), m);
    EXPECT_EQ(fromProto(toProto(m)), m);
    EXPECT_NE(toProto(m), proto::VISUAL_MODE_UNSPECIFIED);
    m = nextVisualMode(m);
  }
  EXPECT_EQ(m, VisualMode::kFull6d) << "the cycle returns after three";
  EXPECT_EQ(names, (std::set<std::string_view>{"full6d", "orientation3d", "fixed"}));
  EXPECT_FALSE(parseVisualMode("6d"));
  EXPECT_FALSE(parseVisualMode(""));
  EXPECT_FALSE(fromProto(proto::VISUAL_MODE_UNSPECIFIED));
  EXPECT_FALSE(fromProto(static_cast<proto::VisualMode>(17)));
}

TEST(LinkEnums, DepthProxyNamesCycleAndProtoRoundTrip) {
  std::set<std::string_view> names;
  DepthProxy p = DepthProxy::kFixed;
  for (int i = 0; i < 3; ++i) {
    names.insert(depthProxyName(p));
    EXPECT_EQ(parseDepthProxy(depthProxyName(p)), p);
    EXPECT_EQ(fromProto(toProto(p)), p);
    EXPECT_NE(toProto(p), proto::DEPTH_PROXY_UNSPECIFIED);
    p = nextDepthProxy(p);
  }
  EXPECT_EQ(p, DepthProxy::kFixed) << "the cycle returns after three";
  EXPECT_EQ(names, (std::set<std::string_view>{"fixed", "radius", "grid"}));
  EXPECT_FALSE(parseDepthProxy("sphere"));
  EXPECT_FALSE(parseDepthProxy(""));
  EXPECT_FALSE(fromProto(proto::DEPTH_PROXY_UNSPECIFIED)) << "unspecified: nobody chose, not fixed";
  EXPECT_FALSE(fromProto(static_cast<proto::DepthProxyProto>(17)));
}

TEST(LinkEnums, ChromaProtoRoundTrip) {
  for (ChromaSubsampling s : {ChromaSubsampling::k420, ChromaSubsampling::k422, ChromaSubsampling::k444,
                              ChromaSubsampling::kGray})
    EXPECT_EQ(fromProto(toProto(s)), s);
  EXPECT_FALSE(fromProto(static_cast<proto::ChromaSubsampling>(9)));
}

TEST(LinkEnums, SphereRadiusRange) {
  EXPECT_TRUE(acceptedSphereRadius(kMinSphereRadius));
  EXPECT_TRUE(acceptedSphereRadius(kMaxSphereRadius));
  EXPECT_FALSE(acceptedSphereRadius(std::nextafter(kMinSphereRadius, 0.0)));
  EXPECT_FALSE(acceptedSphereRadius(std::nextafter(kMaxSphereRadius, 2e3)));
  for (double bad : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()})
    EXPECT_FALSE(acceptedSphereRadius(bad)) << bad;
}

}  // namespace
}  // namespace telesphere::link
