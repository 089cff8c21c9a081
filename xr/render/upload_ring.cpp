// SPDX-License-Identifier: MIT
/// @brief UploadRing: slots in a persistently mapped buffer, handed to decoders, fenced copies.
#include "xr/render/upload_ring.h"

#include <algorithm>
#include <cstdio>

#include "shaders/gl_api.h"

namespace telesphere::xr::render {
namespace {

/// Slot starts (and the planes in them) on this boundary: page-aligned copy sources.
constexpr std::size_t kSlotAlignment = 4096;

std::size_t alignUp(std::size_t n) { return (n + kSlotAlignment - 1) / kSlotAlignment * kSlotAlignment; }

constexpr GLbitfield kMapFlags = GL_MAP_WRITE_BIT | GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;

bool fenceSignalled(void* fence) {
  const GLenum r = glClientWaitSync(static_cast<GLsync>(fence), GL_SYNC_FLUSH_COMMANDS_BIT, 0);
  return r == GL_ALREADY_SIGNALED || r == GL_CONDITION_SATISFIED;
}

void deleteFence(void*& fence) {
  if (fence) glDeleteSync(static_cast<GLsync>(fence));
  fence = nullptr;
}

}  // namespace

std::shared_ptr<const UploadSlot> UploadSlotSource::take(const PlaneLayout& layout) {
  std::lock_guard lock(mutex_);
  Buffer* current = buffers_.empty() || buffers_.back()->retired ? nullptr : buffers_.back().get();
  if (!current || current->layout != layout) {
    ++counts_.other_layout;
    return nullptr;
  }
  const auto it = std::find(current->states.begin(), current->states.end(), State::kFree);
  if (it == current->states.end()) {
    ++counts_.none_free;
    return nullptr;
  }
  const int index = int(it - current->states.begin());
  *it = State::kHeld;
  ++counts_.taken;
  // The release keeps this source alive; the Buffer stays while one of its slots is held.
  std::shared_ptr<UploadSlotSource> self = shared_from_this();
  return std::shared_ptr<const UploadSlot>(&current->slots[std::size_t(index)],
                                           [self, current, index](const UploadSlot*) { self->release(current, index); });
}

void UploadSlotSource::release(Buffer* buffer, int index) {
  std::lock_guard lock(mutex_);
  const auto i = std::size_t(index);
  // A slot the GL copied from waits for its fence (UploadRing::reclaim); one never copied is free.
  buffer->states[i] = buffer->fences[i] ? State::kCopying : State::kFree;
}

UploadSlotSource::Counts UploadSlotSource::counts() const {
  std::lock_guard lock(mutex_);
  return counts_;
}

UploadRing::UploadRing(int slots)
    : slots_(std::max(0, slots)), source_(slots_ > 0 ? std::make_shared<UploadSlotSource>() : nullptr) {}

UploadRing::~UploadRing() {
  if (!source_) return;
  std::lock_guard lock(source_->mutex_);
  for (auto& buffer : source_->buffers_) {
    const bool held = std::count(buffer->states.begin(), buffer->states.end(), UploadSlotSource::State::kHeld) > 0;
    if (held) {
      // Someone still reads these planes: the mapping must outlive them (it goes with the context).
      std::fprintf(stderr, "upload ring: camera planes still held at shutdown; their %.2f MB buffer stays mapped\n",
                   double(buffer->slots.size() * alignUp(buffer->layout.bytes())) / 1e6);
      buffer->retired = true;
      continue;
    }
    for (auto& fence : buffer->fences) {
      if (fence) glClientWaitSync(static_cast<GLsync>(fence), GL_SYNC_FLUSH_COMMANDS_BIT, GLuint64(1'000'000'000));
      deleteFence(fence);
    }
    glUnmapNamedBuffer(buffer->gl_buffer);
    glDeleteBuffers(1, &buffer->gl_buffer);
    buffer->gl_buffer = 0;
  }
}

bool UploadRing::preparedFor(const PlaneLayout& layout) const {
  if (!source_) return false;
  std::lock_guard lock(source_->mutex_);
  return !source_->buffers_.empty() && !source_->buffers_.back()->retired && source_->buffers_.back()->layout == layout;
}

bool UploadRing::prepare(const PlaneLayout& layout, std::string* error) {
  if (!source_) {
    *error = "the upload ring is off (0 slots)";
    return false;
  }
  if (preparedFor(layout)) return true;
  if (layout.width <= 0 || layout.height <= 0 || layout.chroma_width < 0 || layout.chroma_height < 0) {
    *error = "upload ring: no images of " + std::to_string(layout.width) + "x" + std::to_string(layout.height);
    return false;
  }
  const std::size_t slot_bytes = alignUp(layout.lumaBytes()) + 2 * alignUp(layout.chromaBytes());
  const std::size_t total = slot_bytes * std::size_t(slots_);
  GLuint name = 0;
  glCreateBuffers(1, &name);
  glNamedBufferStorage(name, GLsizeiptr(total), nullptr, kMapFlags);
  auto* mapped = static_cast<std::uint8_t*>(glMapNamedBufferRange(name, 0, GLsizeiptr(total), kMapFlags));
  if (!mapped) {
    glDeleteBuffers(1, &name);
    *error = "upload ring: cannot map a persistent buffer of " + std::to_string(slots_) + " x " +
             std::to_string(slot_bytes / 1000000.0) + " MB (GL error " + std::to_string(glGetError()) + ")";
    return false;
  }
  auto buffer = std::make_unique<UploadSlotSource::Buffer>();
  buffer->gl_buffer = name;
  buffer->layout = layout;
  const bool grey = layout.chromaBytes() == 0;
  for (int i = 0; i < slots_; ++i) {
    UploadSlot slot;
    slot.buffer = name;
    slot.index = i;
    slot.layout = layout;
    slot.y_offset = std::size_t(i) * slot_bytes;
    slot.u_offset = slot.y_offset + alignUp(layout.lumaBytes());
    slot.v_offset = slot.u_offset + alignUp(layout.chromaBytes());
    slot.y = mapped + slot.y_offset;
    slot.u = grey ? nullptr : mapped + slot.u_offset;
    slot.v = grey ? nullptr : mapped + slot.v_offset;
    buffer->slots.push_back(slot);
  }
  buffer->states.assign(std::size_t(slots_), UploadSlotSource::State::kFree);
  buffer->fences.assign(std::size_t(slots_), nullptr);
  std::lock_guard lock(source_->mutex_);
  for (auto& old : source_->buffers_) old->retired = true;
  source_->buffers_.push_back(std::move(buffer));
  return true;
}

void UploadRing::reclaim() {
  if (!source_) return;
  using State = UploadSlotSource::State;
  std::lock_guard lock(source_->mutex_);
  auto& buffers = source_->buffers_;
  for (auto& buffer : buffers)
    for (std::size_t i = 0; i < buffer->states.size(); ++i)
      if (buffer->states[i] == State::kCopying && fenceSignalled(buffer->fences[i])) {
        deleteFence(buffer->fences[i]);
        buffer->states[i] = State::kFree;
      }
  // Retired buffers whose slots are all back are freed (their copies are done: they are free).
  std::erase_if(buffers, [](std::unique_ptr<UploadSlotSource::Buffer>& buffer) {
    if (!buffer->retired || std::any_of(buffer->states.begin(), buffer->states.end(),
                                        [](State s) { return s != State::kFree; }))
      return false;
    for (auto& fence : buffer->fences) deleteFence(fence);
    glUnmapNamedBuffer(buffer->gl_buffer);
    glDeleteBuffers(1, &buffer->gl_buffer);
    return true;
  });
}

void UploadRing::fenceCopy(const UploadSlot& slot) {
  if (!source_) return;
  std::lock_guard lock(source_->mutex_);
  for (auto& buffer : source_->buffers_) {
    if (buffer->gl_buffer != slot.buffer) continue;
    void*& fence = buffer->fences[std::size_t(slot.index)];
    deleteFence(fence);  // copied again (a calibration applied live): the newer copy counts
    fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    return;
  }
}

UploadRing::Occupancy UploadRing::occupancy() const {
  Occupancy o;
  if (!source_) return o;
  std::lock_guard lock(source_->mutex_);
  if (source_->buffers_.empty()) return o;
  for (const auto s : source_->buffers_.back()->states) {
    if (s == UploadSlotSource::State::kFree) ++o.free;
    else if (s == UploadSlotSource::State::kHeld) ++o.held;
    else ++o.copying;
  }
  return o;
}

}  // namespace telesphere::xr::render
