// SPDX-License-Identifier: MIT
/// @brief The sphere sweep's pair costs on the GPU (#35): the cost volume SphereSweep::pairCosts
///        computes on one CPU core (tiles × hypotheses ZNCCs of 5 × 5 bilinear samples, two thirds
///        of a sweep's time), as a compute shader (shaders/sphere_sweep_costs.comp), one invocation
///        per tile and hypothesis. The sweep's own tables go to the GPU once (its taps: the same
///        integer bilinear samples, so every sample is equal); per pair the other image and the
///        reference patches go up and the costs come back, and the CPU decides as before
///        (SphereSweep::decide: ambiguity, the earlier views, holes, the median). The costs differ
///        from the CPU's in their last bits only (the sums add in another order).
///
///        Needs a current OpenGL 4.5 context (compute shaders, shader storage buffers) on the
///        calling thread, for construction, every call and destruction.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "shaders/gl_objects.h"
#include "xr/depth/sphere_sweep.h"

namespace telesphere::xr::depth {

class GpuSweepCosts {
 public:
  /// For `sweep` (which must outlive this): its taps uploaded, the program compiled. Nothing, with
  /// the reason, where the context cannot (no compute shaders, the shader file missing).
  static std::unique_ptr<GpuSweepCosts> create(const SphereSweep& sweep, std::string* out_error = nullptr);

  /// The pair's cost volume into `costs`, as SphereSweep::pairCosts lays it out (tiles without
  /// texture are left infinite; unusable hypotheses hold what they hold: decide() ignores them).
  /// False, with the reason, for patches or an image of other sizes or a GL error.
  bool pairCosts(const SphereSweep::ReferencePatches& patches, const GreyImage& other, std::vector<float>& costs,
                 std::string* out_error = nullptr);

  /// The whole sweep with the pair's costs from here: SphereSweep::estimate's result. A grid with
  /// no tile matched where the images do not fit or the GPU fails (the reason in out_error).
  SweepResult estimate(const GreyImage& reference, const GreyImage& other, const std::vector<EarlierView>& earlier = {},
                       std::string* out_error = nullptr);

  /// Bytes the sweep's taps take on the GPU.
  std::size_t tableBytes() const { return table_bytes_; }

 private:
  explicit GpuSweepCosts(const SphereSweep& sweep) : sweep_(sweep) {}

  const SphereSweep& sweep_;
  gl::GlProgram program_;
  gl::GlBuffer taps_, reference_a_, reference_aa_, costs_;
  gl::GlTexture other_image_;
  int width_ = 0, height_ = 0;
  std::size_t table_bytes_ = 0;
  SphereSweep::ReferencePatches patches_;  ///< estimate()'s, kept between pairs
  std::vector<float> costs_read_;
};

}  // namespace telesphere::xr::depth
