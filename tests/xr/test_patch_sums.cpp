// SPDX-License-Identifier: MIT
/// @brief patchSums (xr/depth/patch_sums.h): the AVX2 version against the scalar reference on
///        seeded random images and taps — every patch size from 1 to 49 (whole steps of eight
///        and the rest), taps at the last positions the four-byte reads allow in an image whose
///        last byte is followed by an inaccessible page (a gather past it faults: the sanitizers
///        do not see gathers), a stride wider than the image — and gatherSafe at the image's end.
///        patchCosts, a tile's hypotheses in one call, gives each patch's patchCost to the bit.
#include <gtest/gtest.h>

#include <sys/mman.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "xr/depth/patch_sums.h"

namespace telesphere::xr::depth {
namespace {

/// `bytes` of memory whose last byte is followed by a page no one may read.
class GuardedBuffer {
 public:
  explicit GuardedBuffer(std::size_t bytes) : bytes_(bytes) {
    page_ = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
    mapped_ = (bytes + page_ - 1) / page_ * page_ + page_;
    base_ = static_cast<std::uint8_t*>(mmap(nullptr, mapped_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0));
    if (base_ == MAP_FAILED) throw std::runtime_error("mmap failed");
    if (mprotect(base_ + mapped_ - page_, page_, PROT_NONE) != 0) throw std::runtime_error("mprotect failed");
  }
  ~GuardedBuffer() { munmap(base_, mapped_); }
  GuardedBuffer(const GuardedBuffer&) = delete;
  GuardedBuffer& operator=(const GuardedBuffer&) = delete;
  std::uint8_t* data() { return base_ + mapped_ - page_ - bytes_; }

 private:
  std::size_t bytes_, page_ = 0, mapped_ = 0;
  std::uint8_t* base_ = nullptr;
};

TEST(PatchSums, TheAvx2SumsAreTheScalarSumsUpToRoundingOrder) {
  if (!patchSumsSimdAvailable()) GTEST_SKIP() << "this CPU has no AVX2";
  std::mt19937 rng(3535);
  for (const auto& [width, height, stride] : {std::tuple{480, 270, 480}, std::tuple{37, 9, 40}, std::tuple{4, 3, 4}}) {
    SCOPED_TRACE(std::to_string(width) + "x" + std::to_string(height) + " stride " + std::to_string(stride));
    // Exactly the bytes the image needs, its last row's last byte just before the guard page.
    const std::size_t bytes = static_cast<std::size_t>(stride) * (height - 1) + width;
    GuardedBuffer buffer(bytes);
    std::uint8_t* image = buffer.data();
    std::uniform_int_distribution<int> grey(0, 255);
    for (std::size_t i = 0; i < bytes; ++i) image[i] = static_cast<std::uint8_t>(grey(rng));
    std::uniform_real_distribution<double> ux(0.0, width - 1.0), uy(0.0, height - 1.0), ua(-128.0, 128.0);
    for (int n = 1; n <= 49; ++n) {
      std::vector<BilinearTap> taps;
      std::vector<float> a;
      while (static_cast<int>(taps.size()) < n) {
        // Every fourth tap at the last block the four-byte reads allow, else anywhere allowed.
        const Eigen::Vector2d p = taps.size() % 4 == 3 ? Eigen::Vector2d(width - 4.0 + 0.999, height - 2.0 + 0.5)
                                                       : Eigen::Vector2d(ux(rng), uy(rng));
        const BilinearTap t = bilinearTap(p, width, height);
        if (!gatherSafe(t, width, height)) continue;
        taps.push_back(t);
        a.push_back(static_cast<float>(ua(rng)));
      }
      const PatchSums scalar = patchSumsScalar(image, stride, taps.data(), a.data(), n);
      const PatchSums simd = patchSums(image, stride, taps.data(), a.data(), n, true);
      // Float rounding of n additions of terms up to 128 (b − 128), 128² and 128 · 128 in size.
      const double rounding = 2 * n * std::numeric_limits<float>::epsilon() * n;
      EXPECT_NEAR(simd.b, scalar.b, rounding * 128.0 + 1e-4) << n;
      EXPECT_NEAR(simd.bb, scalar.bb, rounding * 128.0 * 128.0 + 1e-4) << n;
      EXPECT_NEAR(simd.ab, scalar.ab, rounding * 128.0 * 128.0 + 1e-4) << n;
    }
  }
}

TEST(PatchSums, ManyPatchesCostsAreEachPatchsCostToTheBit) {
  // What the sweep's bench figures rest on: a tile against all its hypotheses in one call gives
  // the costs one patch at a time gives, bit for bit (the AVX2 sums of each, the scalar rest, the
  // same float operations for the cost), with unusable patches and textureless ones infinite.
  std::mt19937 rng(20261129);
  const int width = 97, height = 61;
  std::vector<std::uint8_t> image(static_cast<std::size_t>(width) * height);
  std::uniform_int_distribution<int> grey(0, 255);
  for (auto& v : image) v = static_cast<std::uint8_t>(grey(rng));
  std::uniform_real_distribution<double> ux(0.0, width - 4.0), uy(0.0, height - 2.0), ua(-100.0, 100.0);
  std::bernoulli_distribution unusable(0.2), flat(0.15);
  int infinite = 0, compared = 0;
  for (const int n : {1, 7, 8, 9, 25, 49})
    for (const int patches : {1, 5, 8, 13, 48}) {
      std::vector<float> a(n);
      float sum_aa = 0;
      for (float& v : a) {
        v = static_cast<float>(ua(rng));
        sum_aa += v * v;
      }
      std::vector<BilinearTap> taps;
      std::vector<std::uint8_t> usable(patches);
      for (int p = 0; p < patches; ++p) {
        usable[p] = unusable(rng) ? 0 : 1;
        const bool textureless = flat(rng);  // every tap at one pixel: no variance
        const Eigen::Vector2d at(std::floor(ux(rng)), std::floor(uy(rng)));
        for (int i = 0; i < n; ++i) taps.push_back(bilinearTap(textureless ? at : Eigen::Vector2d(ux(rng), uy(rng)), width, height));
      }
      for (const bool simd : {false, true}) {
        std::vector<float> cost(patches, -1.0F);
        patchCosts(image.data(), width, taps.data(), a.data(), sum_aa, n, patches, usable.data(), cost.data(), simd);
        for (int p = 0; p < patches; ++p) {
          const float want = usable[p] ? patchCost(patchSums(image.data(), width, taps.data() + static_cast<std::size_t>(p) * n,
                                                             a.data(), n, simd),
                                                   sum_aa, n)
                                       : std::numeric_limits<float>::infinity();
          EXPECT_EQ(std::memcmp(&cost[p], &want, sizeof(float)), 0)
              << "n " << n << ", patch " << p << " of " << patches << ", simd " << simd << ": " << cost[p] << " against " << want;
          infinite += std::isinf(want);
          ++compared;
        }
      }
    }
  EXPECT_EQ(compared, 2 * 6 * (1 + 5 + 8 + 13 + 48));
  EXPECT_GT(infinite, 20);  // both kinds of infinite cost were met
}

TEST(PatchSums, OnlyTapsInTheLastBlockRowsLastThreePixelsAreUnsafe) {
  const int w = 10, h = 6;
  EXPECT_TRUE(gatherSafe(bilinearTap({6.5, 4.5}, w, h), w, h));   // x0 6: reads to 9, the last pixel
  EXPECT_FALSE(gatherSafe(bilinearTap({7.5, 4.5}, w, h), w, h));  // x0 7: would read 10 and 11
  EXPECT_FALSE(gatherSafe(bilinearTap({9.0, 5.0}, w, h), w, h));  // the last pixel itself
  EXPECT_TRUE(gatherSafe(bilinearTap({8.5, 3.5}, w, h), w, h));   // a row above: the next row follows
  EXPECT_TRUE(gatherSafe(bilinearTap({0.0, 5.0}, w, h), w, h));
}

}  // namespace
}  // namespace telesphere::xr::depth
