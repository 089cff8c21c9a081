// SPDX-License-Identifier: MIT
/// @brief The camera image off the frame's critical path (DESIGN.md §4, issue #16): a ring of
///        slots in one persistently mapped GL buffer. Decoder threads take a free slot and decode
///        straight into it (no GL call: the mapping is coherent); the render thread only issues
///        the copies from the slot into the plane textures, and a fence. A slot is given out again
///        only when nobody holds its planes any more *and* its fence has signalled, so the decoder
///        never writes what the GL still reads. With no free slot (or before the ring knows the
///        images' size) the decoder falls back to its own memory, which is counted.
///
///        Two objects: UploadSlotSource is the thread-safe side the decoders see (take a slot;
///        the last holder's release gives it back); UploadRing lives on the render thread, owns
///        the GL buffers and fences, and must be used and destroyed with its context current.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "xr/render/upload_slot.h"

namespace telesphere::xr::render {

class UploadRing;

class UploadSlotSource : public std::enable_shared_from_this<UploadSlotSource> {
 public:
  /// A free slot for planes of `layout`, or null when none is free or the ring is not (yet) made
  /// for this layout. The slot goes back when the last copy of the pointer is gone.
  std::shared_ptr<const UploadSlot> take(const PlaneLayout& layout);

  struct Counts {
    std::uint64_t taken = 0;         ///< slots given out
    std::uint64_t none_free = 0;     ///< asked while every slot was held or still being copied
    std::uint64_t other_layout = 0;  ///< asked for a layout the ring is not made for (or no ring yet)
  };
  Counts counts() const;

 private:
  friend class UploadRing;
  enum class State { kFree, kHeld, kCopying };
  /// One GL buffer of `slots.size()` slots (a ring is remade when the images change size; the
  /// old buffer is retired and freed once all its slots are back).
  struct Buffer {
    unsigned int gl_buffer = 0;
    PlaneLayout layout;
    std::vector<UploadSlot> slots;
    std::vector<State> states;
    std::vector<void*> fences;  ///< GLsync of the last copy from each slot; only the render thread reads them
    bool retired = false;
  };
  void release(Buffer* buffer, int index);

  mutable std::mutex mutex_;
  std::vector<std::unique_ptr<Buffer>> buffers_;  ///< the current one last
  Counts counts_;
};

class UploadRing {
 public:
  /// `slots` images (a stereo frame takes two); 0 turns the ring off (source() is null). No GL
  /// call here: the buffer is made by prepare().
  explicit UploadRing(int slots);
  /// Waits (≤ 1 s) for copies in flight and frees the buffers. Slots still held by someone
  /// (planes kept beyond the renderer) leave their buffer mapped and allocated: logged.
  ~UploadRing();
  UploadRing(const UploadRing&) = delete;
  UploadRing& operator=(const UploadRing&) = delete;

  /// What the decoders take slots from; null when the ring is off.
  std::shared_ptr<UploadSlotSource> source() const { return source_; }
  int slots() const { return slots_; }

  /// Makes the ring for images of `layout` (no-op when it already is; the previous buffer is
  /// retired). False with the reason when the GL cannot map such a buffer.
  bool prepare(const PlaneLayout& layout, std::string* error);
  /// Where the ring is made for, if anywhere.
  bool preparedFor(const PlaneLayout& layout) const;
  /// Slots whose copies are done and whose planes nobody holds become free again; retired
  /// buffers with every slot back are freed. Fences are polled, never waited for. Once a frame.
  void reclaim();
  /// After the copy commands that read `slot` were issued: fences them.
  void fenceCopy(const UploadSlot& slot);

  struct Occupancy {
    int free = 0, held = 0, copying = 0;
  };
  /// Of the current buffer's slots.
  Occupancy occupancy() const;

 private:
  int slots_;
  std::shared_ptr<UploadSlotSource> source_;
};

}  // namespace telesphere::xr::render
