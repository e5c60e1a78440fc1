// SPDX-License-Identifier: MIT
#include "dsm/run/realtime_wait.h"

#include <gtest/gtest.h>

namespace dsm {
namespace {

using Clock = RealtimeWait::Clock;
using std::chrono::milliseconds;

// 20 Hz: frame i released at 0, frame i + 1 due at 50 ms, frame i + 2 at 100 ms.
const Clock::time_point r0{};
const Clock::time_point r1 = r0 + milliseconds(50);
const Clock::time_point r2 = r0 + milliseconds(100);

TEST(RealtimeWait, KeepsTheNextFramesFirstPoseWithinItsBudget) {
  RealtimeWait wait;
  // Busy up to 9 ms after the wait point (+5), up to 12 ms to a first pose: the next frame's
  // first pose within 45 ms of its release.
  wait.Record(10.0, 4.0, 12.0);
  wait.Record(10.0, 9.0, 8.0);
  EXPECT_EQ(wait.Deadline(r0, r1, r2), r1 + milliseconds(45 - 14 - 12));
  // Slower first poses leave less.
  wait.Record(10.0, 3.0, 30.0);
  EXPECT_EQ(wait.Deadline(r0, r1, r2), r1 + milliseconds(45 - 14 - 30));
  // None left: the wait ends when the next frame comes.
  wait.Record(10.0, 3.0, 40.0);
  EXPECT_EQ(wait.Deadline(r0, r1, r2), r1);
  // Busy for longer than a frame: the frame after next is what bounds the wait.
  wait.Record(10.0, 70.0, 5.0);
  EXPECT_EQ(wait.Deadline(r0, r1, r2), r2 - milliseconds(75));
  // The last frame: nothing comes after it, nothing to wait for without a target.
  EXPECT_EQ(wait.Deadline(r0, std::nullopt, std::nullopt), r0);
  RealtimeWait bounded(30.0);
  bounded.Record(10.0, 4.0, 5.0);
  EXPECT_EQ(bounded.Deadline(r0, r1, std::nullopt), r0 + milliseconds(30 - 9));
}

TEST(RealtimeWait, NeverLongEnoughToDropAFrame) {
  RealtimeWait wait(40.0);
  for (double busy : {4.0, 9.0, 5.0}) wait.Record(10.0, busy, 5.0);
  // Busy up to 9 ms (+5): the frame after next must find tracking free.
  EXPECT_EQ(wait.Deadline(r0, std::nullopt, r2), r2 - milliseconds(14));
  // Near the end: the latency target alone.
  EXPECT_EQ(wait.Deadline(r0, std::nullopt, std::nullopt), r0 + milliseconds(40 - 14));
  // Only the recent frames count: ten quick ones push a slow one out.
  wait.Record(10.0, 60.0, 5.0);
  EXPECT_EQ(wait.Deadline(r0, std::nullopt, r2), r2 - milliseconds(65));
  for (size_t k = 0; k < RealtimeWait::kRecentFrames; ++k) wait.Record(10.0, 3.0, 5.0);
  EXPECT_EQ(wait.Deadline(r0, std::nullopt, r2), r2 - milliseconds(8));
}

TEST(RealtimeWait, KeepsMostFramesWithinTheLatencyTarget) {
  RealtimeWait wait(40.0);
  for (int k = 0; k < 93; ++k) wait.Record(10.0, 3.0, 5.0);
  for (int k = 0; k < 7; ++k) wait.Record(80.0, 3.0, 5.0);  // 7 of the last 100 late: one more may be.
  EXPECT_EQ(wait.Deadline(r0, std::nullopt, r2), r2 - milliseconds(8));
  wait.Record(80.0, 3.0, 5.0);  // 8 of 100: the rest wait within the target.
  EXPECT_EQ(wait.Deadline(r0, std::nullopt, r2), r0 + milliseconds(32));
  for (size_t k = 0; k < RealtimeWait::kLatencyWindow; ++k) wait.Record(10.0, 3.0, 5.0);
  EXPECT_EQ(wait.Deadline(r0, std::nullopt, r2), r2 - milliseconds(8));
}

TEST(RealtimeWait, WithoutATargetOnlyTheNextFramesBound) {
  RealtimeWait wait;
  for (int k = 0; k < 50; ++k) wait.Record(90.0, 3.0, 5.0);  // Late frames do not matter.
  EXPECT_EQ(wait.Deadline(r0, std::nullopt, r2), r2 - milliseconds(8));
  EXPECT_EQ(wait.Deadline(r0, std::nullopt, std::nullopt), r0);
}

TEST(RealtimeWait, ATargetOfZeroNeverWaits) {
  RealtimeWait wait(0.0);
  wait.Record(10.0, 3.0, 5.0);
  EXPECT_EQ(wait.Deadline(r0, std::nullopt, r2), r0);
  EXPECT_EQ(wait.Deadline(r0, std::nullopt, std::nullopt), r0);
}

}  // namespace
}  // namespace dsm
