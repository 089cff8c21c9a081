// SPDX-License-Identifier: MIT
/// @brief GpuSweepCosts: the taps in a shader storage buffer, the other image in an R8UI texture,
///        one compute dispatch a pair, the costs read back.
#include "xr/depth/gpu_sweep_costs.h"

#include <limits>

#include <algorithm>

#include "shaders/shader_program.h"
#include "xr/depth/patch_sums.h"

namespace telesphere::xr::depth {
namespace {

constexpr int kLocalSize = 64;  // shaders/sphere_sweep_costs.comp's local_size_x

bool fail(std::string* out_error, const std::string& message) {
  if (out_error) *out_error = "GPU sweep: " + message;
  return false;
}

/// The first GL error since the last check, as text; empty when none.
std::string glErrorText() {
  const GLenum error = glGetError();
  if (error == GL_NO_ERROR) return "";
  while (glGetError() != GL_NO_ERROR) {
  }
  return "GL error 0x" + [&] {
    static const char* hex = "0123456789abcdef";
    std::string out;
    for (int shift = 12; shift >= 0; shift -= 4) out += hex[(error >> shift) & 0xF];
    return out;
  }();
}

}  // namespace

std::unique_ptr<GpuSweepCosts> GpuSweepCosts::create(const SphereSweep& sweep, std::string* out_error) {
  std::unique_ptr<GpuSweepCosts> gpu(new GpuSweepCosts(sweep));
  glGetError();  // a caller's earlier error is not ours
  // The samples' shift (patch_sums.h) in the shader's fixed point: b · 65536.
  const std::string offset = "TS_GREY_OFFSET_FIXED " + std::to_string(static_cast<int>(kPatchGreyOffset) * 65536);
  auto program = gl::loadComputeProgram("sphere_sweep_costs.comp", {offset}, out_error);
  if (!program) {
    if (out_error) *out_error = "GPU sweep: " + *out_error;
    return nullptr;
  }
  gpu->program_ = std::move(*program);
  const std::size_t tiles = static_cast<std::size_t>(sweep.tileCount());
  const std::size_t hypotheses = static_cast<std::size_t>(sweep.options().hypotheses);
  const std::size_t samples = static_cast<std::size_t>(sweep.samplesPerTile());
  GLint max_groups = 0;
  glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &max_groups);
  if ((tiles * hypotheses + kLocalSize - 1) / kLocalSize > static_cast<std::size_t>(max_groups)) {
    fail(out_error, std::to_string(tiles * hypotheses) + " tiles × hypotheses need more than the GPU's " +
                        std::to_string(max_groups) + " work groups");
    return nullptr;
  }
  // The taps are one storage block: a driver may hold no more than 2^27 bytes in one (the minimum
  // GL guarantees; 1° tiles with 48 hypotheses need about 600 MB).
  GLint64 max_block = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
  const std::size_t largest = std::max(sweep.otherTaps().size() * sizeof(BilinearTap), tiles * hypotheses * sizeof(float));
  if (largest > static_cast<std::size_t>(max_block)) {
    fail(out_error, "the sweep's tables take " + std::to_string(largest) + " bytes in one storage block, the GPU allows " +
                        std::to_string(max_block));
    return nullptr;
  }
  gpu->width_ = sweep.otherWidth();
  gpu->height_ = sweep.otherHeight();
  const std::vector<BilinearTap>& taps = sweep.otherTaps();
  static_assert(sizeof(BilinearTap) == 8, "a tap is the shader's uvec2: x | y << 16, wx | wy << 16");
  gpu->table_bytes_ = taps.size() * sizeof(BilinearTap);
  const auto storage = [](gl::GlBuffer& buffer, std::size_t bytes, const void* data, GLbitfield flags) {
    buffer = gl::createBuffer();
    glNamedBufferStorage(buffer.id(), static_cast<GLsizeiptr>(std::max<std::size_t>(bytes, 4)), data, flags);
  };
  storage(gpu->taps_, gpu->table_bytes_, taps.empty() ? nullptr : taps.data(), 0);
  storage(gpu->reference_a_, tiles * samples * sizeof(float), nullptr, GL_DYNAMIC_STORAGE_BIT);
  storage(gpu->reference_aa_, tiles * sizeof(float), nullptr, GL_DYNAMIC_STORAGE_BIT);
  storage(gpu->costs_, tiles * hypotheses * sizeof(float), nullptr, 0);
  gpu->other_image_ = gl::createTexture(GL_TEXTURE_2D);
  glTextureStorage2D(gpu->other_image_.id(), 1, GL_R8UI, gpu->width_, gpu->height_);
  // An integer texture is complete only with nearest filtering (texelFetch reads it either way).
  glTextureParameteri(gpu->other_image_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(gpu->other_image_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  if (const std::string error = glErrorText(); !error.empty()) {
    fail(out_error, "setting up the tables: " + error);
    return nullptr;
  }
  return gpu;
}

bool GpuSweepCosts::pairCosts(const SphereSweep::ReferencePatches& patches, const GreyImage& other, std::vector<float>& costs,
                              std::string* out_error) {
  const std::size_t tiles = static_cast<std::size_t>(sweep_.tileCount());
  const std::size_t hypotheses = static_cast<std::size_t>(sweep_.options().hypotheses);
  const std::size_t samples = static_cast<std::size_t>(sweep_.samplesPerTile());
  if (patches.textured.size() != tiles || patches.a.size() != tiles * samples || patches.sum_aa.size() != tiles)
    return fail(out_error, "reference patches of another sweep");
  if (!other.pixels || other.width != width_ || other.height != height_ || other.stride < other.width)
    return fail(out_error, "an image of " + std::to_string(other.width) + "x" + std::to_string(other.height) + ", not " +
                               std::to_string(width_) + "x" + std::to_string(height_));
  glGetError();
  // The image rows `stride` apart, bytes unaligned; the caller's unpacking restored afterwards.
  GLint row_length = 0, alignment = 4;
  glGetIntegerv(GL_UNPACK_ROW_LENGTH, &row_length);
  glGetIntegerv(GL_UNPACK_ALIGNMENT, &alignment);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, other.stride);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(other_image_.id(), 0, 0, 0, width_, height_, GL_RED_INTEGER, GL_UNSIGNED_BYTE, other.pixels);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, row_length);
  glPixelStorei(GL_UNPACK_ALIGNMENT, alignment);
  if (tiles > 0) {
    glNamedBufferSubData(reference_a_.id(), 0, static_cast<GLsizeiptr>(patches.a.size() * sizeof(float)), patches.a.data());
    glNamedBufferSubData(reference_aa_.id(), 0, static_cast<GLsizeiptr>(tiles * sizeof(float)), patches.sum_aa.data());
  }
  glUseProgram(program_.id());
  glUniform1i(0, static_cast<GLint>(tiles));
  glUniform1i(1, static_cast<GLint>(hypotheses));
  glUniform1i(2, static_cast<GLint>(samples));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, taps_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, reference_a_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, reference_aa_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, costs_.id());
  glBindTextureUnit(0, other_image_.id());
  const std::size_t invocations = tiles * hypotheses;
  if (invocations > 0) glDispatchCompute(static_cast<GLuint>((invocations + kLocalSize - 1) / kLocalSize), 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  costs.resize(invocations);
  if (invocations > 0)
    glGetNamedBufferSubData(costs_.id(), 0, static_cast<GLsizeiptr>(invocations * sizeof(float)), costs.data());
  glUseProgram(0);
  for (std::size_t i = 0; i < 4; ++i) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, static_cast<GLuint>(i), 0);
  glBindTextureUnit(0, 0);
  if (const std::string error = glErrorText(); !error.empty()) return fail(out_error, "computing the costs: " + error);
  for (std::size_t t = 0; t < tiles; ++t)
    if (!patches.textured[t])
      std::fill(costs.begin() + static_cast<std::ptrdiff_t>(t * hypotheses),
                costs.begin() + static_cast<std::ptrdiff_t>((t + 1) * hypotheses), std::numeric_limits<float>::infinity());
  return true;
}

SweepResult GpuSweepCosts::estimate(const GreyImage& reference, const GreyImage& other, const std::vector<EarlierView>& earlier,
                                    std::string* out_error) {
  if (!sweep_.accepts(reference, other)) {
    fail(out_error, "images of other sizes than the sweep's");
    return sweep_.decide({}, {}, {}, {});
  }
  sweep_.referencePatches(reference, patches_);
  if (!pairCosts(patches_, other, costs_read_, out_error)) return sweep_.decide({}, {}, {}, {});
  return sweep_.decide(reference, patches_, costs_read_, earlier);
}

}  // namespace telesphere::xr::depth
