// SPDX-License-Identifier: MIT
/// @brief projectPatch (xr/depth/patch_projection.h): a patch's samples placed from its four
///        projected corners against every sample projected, over every 4° tile the simulated 195°
///        lens sees at the sweep's 480 × 270, for motions from none to larger than the nearest
///        depth's sphere, at infinity, at 1 m and at the nearest hypothesis (0.25 m): p50 under
///        0.06 px, the worst under 0.4 px (at the image's corners); and what does not project.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

#include "app/bench/prerendered_frames.h"
#include "xr/depth/patch_projection.h"
#include "xr/depth/patch_sums.h"
#include "xr/render/depth_proxy.h"

namespace telesphere::xr {
namespace patch_projection_test {

constexpr int kWidth = 480, kHeight = 270, kSide = 5;

/// The 5 × 5 sample directions of a tile, as the sphere sweep spreads them.
std::vector<Eigen::Vector3f> patch(const render::InverseDepthGrid& grid, int row, int col) {
  std::vector<Eigen::Vector3f> d;
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; j < kSide; ++j) d.push_back(grid.direction(row + (i + 0.5) / kSide, col + (j + 0.5) / kSide).cast<float>());
  return d;
}

TEST(PatchProjection, CornersPlaceTheSamplesWithinAFewHundredthsOfAPixelOfTheirProjections) {
  const calib::CameraCalibration lens = bench::simulatedLens(kWidth, kHeight);
  const render::InverseDepthGrid grid(4.0);
  struct Motion {
    const char* name;
    Eigen::Isometry3d T_view_reference;
  };
  Eigen::Isometry3d barely_turned(Eigen::AngleAxisd(1e-5, Eigen::Vector3d(0.0, 1.0, 0.0)));
  barely_turned.translation() = Eigen::Vector3d(-0.01, 0.0, 0.0);
  // Turned half a turn about the optical axis (upside down) and moved 5 cm: the far tiles swap sides.
  Eigen::Isometry3d upside_down(Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitZ()));
  upside_down.translation() = Eigen::Vector3d(0.05, 0.0, 0.0);
  Eigen::Isometry3d turned(Eigen::AngleAxisd(0.2, Eigen::Vector3d(0.3, 1.0, 0.1).normalized()));
  turned.translation() = Eigen::Vector3d(-0.05, 0.01, 0.02);
  const std::vector<Motion> motions = {{"none", Eigen::Isometry3d::Identity()},
                                       {"1 cm aside", Eigen::Isometry3d(Eigen::Translation3d(-0.01, 0.0, 0.0))},
                                       {"1 cm aside, turned 1e-5 rad", barely_turned},
                                       {"upside down, 5 cm aside", upside_down},
                                       {"turned 11 deg and moved 5 cm", turned},
                                       // Beyond the nearest hypothesis's sphere (0.25 m): rays then cross in front of the view.
                                       {"30 cm aside and ahead", Eigen::Isometry3d(Eigen::Translation3d(0.3, 0.0, -0.3))}};
  for (const Motion& motion : motions)
    for (const double rho : {0.0, 1.0, 4.0}) {
      SCOPED_TRACE(std::string(motion.name) + ", rho " + std::to_string(rho));
      double worst = 0;
      int patches = 0, unprojected = 0;
      Eigen::Vector2d worst_px(0, 0);
      std::vector<double> errors;
      for (int row = 0; row < grid.rows(); ++row)
        for (int col = 0; col < grid.cols(); ++col) {
          Eigen::Vector2d centre;
          // Tiles the reference sees inside its image, as the sweep takes them.
          if (!lens.camera.project(grid.tileCentre(row, col), centre) || centre.x() < 0 || centre.y() < 0 ||
              centre.x() > kWidth - 1 || centre.y() > kHeight - 1)
            continue;
          const std::vector<Eigen::Vector3f> d = patch(grid, row, col);
          std::vector<Eigen::Vector2d> exact(kSide * kSide), corners(kSide * kSide);
          const bool all = depth::projectPatch(lens.camera, d.data(), kSide, motion.T_view_reference, rho, false, exact.data());
          const bool four = depth::projectPatch(lens.camera, d.data(), kSide, motion.T_view_reference, rho, true, corners.data());
          // The corners are samples too: where they do not project, neither does the patch.
          if (!four) {
            EXPECT_FALSE(all);
          }
          if (!all || !four) {
            ++unprojected;
            continue;
          }
          // Only where the patch lands inside the view's image (where the sweep samples it).
          bool inside = true;
          for (const Eigen::Vector2d& p : exact) inside = inside && p.x() >= 0 && p.y() >= 0 && p.x() <= kWidth - 1 && p.y() <= kHeight - 1;
          if (!inside) continue;
          ++patches;
          double tile_worst = 0;
          for (int s = 0; s < kSide * kSide; ++s) tile_worst = std::max(tile_worst, (exact[s] - corners[s]).norm());
          errors.push_back(tile_worst);
          if (tile_worst > worst) {
            worst = tile_worst;
            worst_px = centre;
          }
        }
      ASSERT_GT(patches, 100);
      std::sort(errors.begin(), errors.end());
      const double p50 = errors[errors.size() / 2], p99 = errors[errors.size() * 99 / 100];
      std::printf("%-30s rho %.0f: %4d patches, p50 %.3f p99 %.3f worst %.3f px (tile at %.0f, %.0f), %d not projected\n", motion.name,
                  rho, patches, p50, p99, worst, worst_px.x(), worst_px.y(), unprojected);
      // Measured: p50 0.03–0.05 px, p99 0.16–0.30, the worst 0.19–0.32 px at the image's corners
      // (the lens beyond 90°). The sweep's samples lie 2 px apart.
      EXPECT_LT(p50, 0.06) << "px";
      EXPECT_LT(p99, 0.35) << "px";
      EXPECT_LT(worst, 0.4) << "px";
    }
}

TEST(PatchProjection, APatchThatDoesNotProjectSaysSo) {
  const calib::CameraCalibration lens = bench::simulatedLens(kWidth, kHeight);
  // Straight behind a 195° lens: outside its field of view, every sample and every corner.
  std::vector<Eigen::Vector3f> behind(kSide * kSide, Eigen::Vector3f(0.0F, 0.0F, -1.0F));
  std::vector<Eigen::Vector2d> px(kSide * kSide);
  EXPECT_FALSE(depth::projectPatch(lens.camera, behind.data(), kSide, Eigen::Isometry3d::Identity(), 0.0, false, px.data()));
  EXPECT_FALSE(depth::projectPatch(lens.camera, behind.data(), kSide, Eigen::Isometry3d::Identity(), 0.0, true, px.data()));
  // A point at the camera centre (ρ → ∞ along a ray from a view placed on it) does not project either.
  std::vector<Eigen::Vector3f> ahead(kSide * kSide, Eigen::Vector3f(0.0F, 0.0F, 1.0F));
  const Eigen::Isometry3d T_view_reference(Eigen::Translation3d(0.0, 0.0, -0.25));  // the view 0.25 m ahead, where ρ = 4 puts the point
  EXPECT_FALSE(depth::projectPatch(lens.camera, ahead.data(), kSide, T_view_reference, 4.0, true, px.data()));
}

TEST(PatchProjection, TapsBetweenCornersAreEachInterpolatedSamplesTapToTheBit) {
  // The AVX2 taps (where this CPU has it) against bilinearTap of betweenCorners, one sample at a time,
  // and the scalar path against the same: seeded random corners anywhere inside images from the
  // smallest (2 × 2) to the largest (65536 wide), corners on the image's edges, on half steps of a
  // weight (where rounding turns), and patches of 2 × 2 to 9 × 9 (0 or 1 sample past the last step of four).
  std::mt19937 random(35);
  struct Size {
    int width, height;
  };
  const std::vector<Size> sizes = {{2, 2}, {3, 7}, {480, 270}, {960, 540}, {65536, 3}, {5, 65536}};
  int patches = 0;
  for (const Size& size : sizes)
    for (int n = 2; n <= 9; ++n)
      for (int trial = 0; trial < 400; ++trial) {
        const double max_x = size.width - 1.0, max_y = size.height - 1.0;
        const auto coordinate = [&](double max) {
          switch (trial % 4) {
            case 0: return std::uniform_real_distribution<double>(0.0, max)(random);
            // On the image's edges.
            case 1: return std::bernoulli_distribution(0.5)(random) ? 0.0 : max;
            // Whole pixels plus a half step of a 1/256 weight, or the doubles beside one.
            case 2: {
              const double half = (std::uniform_int_distribution<int>(0, 255)(random) + 0.5) / 256.0;
              const double p = std::min(std::floor(std::uniform_real_distribution<double>(0.0, max)(random)) + half, max);
              const int side = std::uniform_int_distribution<int>(-1, 1)(random);
              return std::clamp(side == 0 ? p : std::nextafter(p, side * 1e9), 0.0, max);
            }
            // A small patch anywhere: all corners within a pixel or two of each other.
            default: return std::uniform_real_distribution<double>(0.0, std::min(max, 2.0))(random);
          }
        };
        depth::PatchCorners corners{{coordinate(max_x), coordinate(max_y)},
                                    {coordinate(max_x), coordinate(max_y)},
                                    {coordinate(max_x), coordinate(max_y)},
                                    {coordinate(max_x), coordinate(max_y)}};
        std::vector<depth::BilinearTap> expected(n * n), simd(n * n + 3), scalar(n * n);
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j)
            expected[i * n + j] = depth::bilinearTap(depth::betweenCorners(corners, n, i, j), size.width, size.height);
        // A guard past the patch: the four-at-a-step version must not write beyond n × n taps.
        std::memset(static_cast<void*>(simd.data()), 0xAB, simd.size() * sizeof(depth::BilinearTap));
        depth::tapsBetweenCorners(corners, n, size.width, size.height, simd.data(), true);
        depth::tapsBetweenCorners(corners, n, size.width, size.height, scalar.data(), false);
        for (int s = 0; s < n * n; ++s) {
          SCOPED_TRACE("size " + std::to_string(size.width) + "x" + std::to_string(size.height) + ", n " + std::to_string(n) +
                       ", sample " + std::to_string(s));
          for (const std::vector<depth::BilinearTap>* got : {&simd, &scalar}) {
            ASSERT_EQ((*got)[s].x, expected[s].x);
            ASSERT_EQ((*got)[s].y, expected[s].y);
            ASSERT_EQ((*got)[s].wx, expected[s].wx);
            ASSERT_EQ((*got)[s].wy, expected[s].wy);
          }
        }
        for (int s = n * n; s < n * n + 3; ++s) {
          std::uint64_t guard = 0;
          std::memcpy(&guard, &simd[s], sizeof(guard));
          ASSERT_EQ(guard, 0xABABABABABABABABULL) << "written past the patch, n " << n;
        }
        ++patches;
      }
  EXPECT_EQ(patches, 6 * 8 * 400);
  std::printf("%d patches, AVX2 %s\n", patches, depth::patchSumsSimdAvailable() ? "compared" : "not on this CPU (scalar only)");
}

TEST(PatchProjection, SumsBetweenCornersAreTheSumsOverTheirTapsToTheBit) {
  // patchSumsBetweenCorners against patchSums over tapsBetweenCorners's taps (eight a step only where
  // every tap is gather-safe, as the sweep asks): seeded random grey images with rows wider than
  // the image, corners anywhere, hugging the last rows and columns (where the taps are summed one
  // at a time or gathered, each side of the half-pixel margin), and patches of 2 × 2 to 9 × 9.
  std::mt19937 random(3535);
  struct Size {
    int width, height, stride;
  };
  const std::vector<Size> sizes = {{2, 2, 2}, {5, 4, 8}, {480, 270, 480}, {61, 37, 64}};
  int patches = 0, gathered = 0;
  for (const Size& size : sizes) {
    std::vector<std::uint8_t> image(static_cast<std::size_t>(size.stride) * size.height);
    for (std::uint8_t& p : image) p = static_cast<std::uint8_t>(random());
    const double max_x = size.width - 1.0, max_y = size.height - 1.0;
    for (int n = 2; n <= 9; ++n)
      for (int trial = 0; trial < 300; ++trial) {
        const auto coordinate = [&](double max) {
          switch (trial % 3) {
            case 0: return std::uniform_real_distribution<double>(0.0, max)(random);
            // Within four pixels of the far edge: every combination of gathered and one-at-a-time.
            case 1: return std::uniform_real_distribution<double>(std::max(0.0, max - 4.0), max)(random);
            default: return std::bernoulli_distribution(0.5)(random) ? max : std::max(0.0, max - 2.5);
          }
        };
        const depth::PatchCorners corners{{coordinate(max_x), coordinate(max_y)},
                                          {coordinate(max_x), coordinate(max_y)},
                                          {coordinate(max_x), coordinate(max_y)},
                                          {coordinate(max_x), coordinate(max_y)}};
        std::vector<float> a(n * n);
        for (float& v : a) v = std::uniform_real_distribution<float>(-60.0F, 60.0F)(random);
        std::vector<depth::BilinearTap> taps(n * n);
        depth::tapsBetweenCorners(corners, n, size.width, size.height, taps.data(), false);
        const bool gather_safe = std::all_of(taps.begin(), taps.end(), [&](const depth::BilinearTap& t) {
          return depth::gatherSafe(t, size.width, size.height);
        });
        gathered += gather_safe ? 1 : 0;
        for (const bool simd : {true, false}) {
          const depth::PatchSums want = depth::patchSums(image.data(), size.stride, taps.data(), a.data(), n * n, simd && gather_safe);
          const depth::PatchSums got =
              depth::patchSumsBetweenCorners(image.data(), size.stride, size.width, size.height, corners, n, a.data(), simd);
          SCOPED_TRACE("size " + std::to_string(size.width) + "x" + std::to_string(size.height) + ", n " + std::to_string(n) +
                       ", trial " + std::to_string(trial) + (simd ? ", simd" : ", scalar"));
          ASSERT_EQ(std::bit_cast<std::uint32_t>(got.b), std::bit_cast<std::uint32_t>(want.b)) << got.b << " " << want.b;
          ASSERT_EQ(std::bit_cast<std::uint32_t>(got.bb), std::bit_cast<std::uint32_t>(want.bb)) << got.bb << " " << want.bb;
          ASSERT_EQ(std::bit_cast<std::uint32_t>(got.ab), std::bit_cast<std::uint32_t>(want.ab)) << got.ab << " " << want.ab;
        }
        ++patches;
      }
  }
  EXPECT_EQ(patches, 4 * 8 * 300);
  // Both sides of the gather-safety taken.
  EXPECT_GT(gathered, patches / 4);
  EXPECT_LT(gathered, patches);
  std::printf("%d patches, %d gather-safe, AVX2 %s\n", patches, gathered,
              depth::patchSumsSimdAvailable() ? "compared" : "not on this CPU (scalar only)");
}

}  // namespace patch_projection_test
}  // namespace telesphere::xr
