// SPDX-License-Identifier: MIT
#include "dsm/system/mapping_thread.h"

#include <future>

#include <gtest/gtest.h>

namespace dsm {
namespace {

// A bounded wait gives up while the keyframe job runs, and succeeds once it is done.
TEST(MappingThread, BoundedWaitForKeyframes) {
  MappingThread thread;
  std::promise<void> go;
  std::shared_future<void> started = go.get_future().share();
  thread.Submit([started] { started.wait(); }, /*keyframe=*/true);
  thread.Submit([] {}, /*keyframe=*/false);
  EXPECT_EQ(thread.KeyframesPending(), 1);
  EXPECT_FALSE(thread.WaitForKeyframesUntil(std::chrono::steady_clock::now() + std::chrono::milliseconds(5)));
  EXPECT_EQ(thread.KeyframesPending(), 1);
  go.set_value();
  EXPECT_TRUE(thread.WaitForKeyframesUntil(std::chrono::steady_clock::now() + std::chrono::seconds(60)));
  EXPECT_EQ(thread.KeyframesPending(), 0);
  // Nothing pending: true at once, even with a deadline already past.
  EXPECT_TRUE(thread.WaitForKeyframesUntil(std::chrono::steady_clock::now() - std::chrono::seconds(1)));
  thread.WaitUntilIdle();
}

}  // namespace
}  // namespace dsm
