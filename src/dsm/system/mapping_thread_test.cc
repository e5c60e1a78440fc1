// SPDX-License-Identifier: MIT
#include "dsm/system/mapping_thread.h"

#include <future>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace dsm {
namespace {

// A bounded wait gives up while the keyframe job runs, and succeeds once it is done (a keyframe
// job without a follow-up settles with itself).
TEST(MappingThread, BoundedWaitForKeyframes) {
  MappingThread thread;
  std::promise<void> go;
  std::shared_future<void> started = go.get_future().share();
  thread.Submit([started] { started.wait(); }, /*keyframe=*/true);
  thread.Submit([] {}, /*keyframe=*/false);
  EXPECT_EQ(thread.KeyframesPending(), 1);
  EXPECT_FALSE(thread.WaitForSettledKeyframesUntil(std::chrono::steady_clock::now() + std::chrono::milliseconds(5)));
  EXPECT_EQ(thread.KeyframesPending(), 1);
  go.set_value();
  EXPECT_TRUE(thread.WaitForSettledKeyframesUntil(std::chrono::steady_clock::now() + std::chrono::seconds(60)));
  EXPECT_EQ(thread.KeyframesPending(), 0);
  EXPECT_EQ(thread.KeyframesUnsettled(), 0);
  // Nothing pending: true at once, even with a deadline already past.
  EXPECT_TRUE(thread.WaitForSettledKeyframesUntil(std::chrono::steady_clock::now() - std::chrono::seconds(1)));
  thread.WaitUntilIdle();
}

// A job's `then` runs right behind it, before anything queued meanwhile by the job itself (as an
// adjustment that yields to the keyframe queues its rest: MappingSide::Adjust).
TEST(MappingThread, AJobsFollowUpRunsRightBehindIt) {
  MappingThread thread;
  std::vector<char> order;  // Written by the mapping thread only, read after WaitUntilIdle.
  std::promise<void> go;
  std::shared_future<void> started = go.get_future().share();
  thread.Submit(
      [&] {
        started.wait();
        thread.Submit([&] { order.push_back('r'); }, false);  // Queued from within a running job.
        order.push_back('a');
      },
      false);
  thread.Submit([&] { order.push_back('k'); }, /*keyframe=*/true, [&] { order.push_back('f'); });
  EXPECT_EQ(thread.KeyframesPending(), 1);  // The keyframe job only, not its follow-up.
  go.set_value();
  thread.WaitUntilIdle();
  EXPECT_EQ(std::string(order.begin(), order.end()), "akfr");
  EXPECT_EQ(thread.KeyframesPending(), 0);
}

// A keyframe is pending until its job finishes and unsettled until its follow-up does too; a
// bounded wait for it to settle gives up while the follow-up runs.
TEST(MappingThread, AKeyframeSettlesWithItsFollowUp) {
  MappingThread thread;
  std::promise<void> go;
  std::shared_future<void> started = go.get_future().share();
  std::promise<void> published;
  thread.Submit([&] { published.set_value(); }, /*keyframe=*/true, [started] { started.wait(); });
  EXPECT_EQ(thread.KeyframesUnsettled(), 1);
  published.get_future().wait();
  thread.WaitForKeyframes();
  EXPECT_EQ(thread.KeyframesPending(), 0);
  EXPECT_EQ(thread.KeyframesUnsettled(), 1);
  EXPECT_FALSE(thread.WaitForSettledKeyframesUntil(std::chrono::steady_clock::now() + std::chrono::milliseconds(5)));
  go.set_value();
  EXPECT_TRUE(thread.WaitForSettledKeyframesUntil(std::chrono::steady_clock::now() + std::chrono::seconds(60)));
  EXPECT_EQ(thread.KeyframesUnsettled(), 0);
  thread.WaitUntilIdle();
}

}  // namespace
}  // namespace dsm
