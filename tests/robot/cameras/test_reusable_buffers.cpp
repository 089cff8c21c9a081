// SPDX-License-Identifier: MIT
/// @brief ReusableBuffers: a held buffer is never handed out again, a released one comes back (its
///        memory kept), and beyond its size the pool hands out fresh buffers it does not keep.
#include <gtest/gtest.h>

#include "robot/cameras/reusable_buffers.h"

namespace telesphere::robot {
namespace {

TEST(ReusableBuffers, HandsOutOnlyWhatNobodyHolds) {
  cameras::ReusableBuffers pool(2);
  auto a = pool.acquire();
  a->resize(1000);
  const std::uint8_t* a_memory = a->data();
  auto b = pool.acquire();
  EXPECT_NE(a.get(), b.get());
  const auto* b_buffer = b.get();
  b.reset();  // e.g. the link sent it
  auto again = pool.acquire();
  EXPECT_EQ(again.get(), b_buffer) << "a released buffer comes back";
  // Both kept buffers held: a fresh one, not kept, so it never comes back.
  auto fresh = pool.acquire();
  EXPECT_NE(fresh.get(), a.get());
  EXPECT_NE(fresh.get(), again.get());
  const auto* fresh_buffer = fresh.get();
  fresh.reset();
  again.reset();
  auto next = pool.acquire();
  EXPECT_NE(next.get(), fresh_buffer);
  EXPECT_EQ(next.get(), b_buffer);
  // A buffer still held elsewhere (a frame in a queue) is not handed out, and keeps its memory
  // for the next frame once released.
  std::shared_ptr<const std::vector<std::uint8_t>> frame = std::move(a);
  auto other = pool.acquire();
  EXPECT_NE(other.get(), frame.get());
  const auto* frame_buffer = frame.get();
  other.reset();
  next.reset();
  frame.reset();
  auto first = pool.acquire();
  auto second = pool.acquire();
  const bool frame_came_back = first.get() == frame_buffer || second.get() == frame_buffer;
  EXPECT_TRUE(frame_came_back);
  EXPECT_EQ((first.get() == frame_buffer ? first : second)->data(), a_memory);
}

}  // namespace
}  // namespace telesphere::robot
