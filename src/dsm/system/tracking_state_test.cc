// SPDX-License-Identifier: MIT
// The tracking state machine's table (tracking_state.h): each transition, and every pair of state
// and event that is none. The System goes through them in run/run_relocalisation_test
// (EveryTrackingStateIsReached).
#include "dsm/system/tracking_state.h"

#include <gtest/gtest.h>

namespace dsm {
namespace {

using S = TrackingState;
using E = TrackingEvent;

TEST(TrackingState, TheMapStartEndsTheInitialisation) {
  EXPECT_EQ(NextTrackingState(S::kInitializing, E::kMapStarted), S::kTracking);
}

TEST(TrackingState, ALoadedMapStartsLost) {
  EXPECT_EQ(NextTrackingState(S::kInitializing, E::kMapLoaded), S::kLost);
}

TEST(TrackingState, ATrackedFrameKeepsTracking) { EXPECT_EQ(NextTrackingState(S::kTracking, E::kTracked), S::kTracking); }

TEST(TrackingState, AFailedFrameIsLost) { EXPECT_EQ(NextTrackingState(S::kTracking, E::kFailed), S::kLost); }

TEST(TrackingState, AFailedRelocalisationStaysLost) { EXPECT_EQ(NextTrackingState(S::kLost, E::kFailed), S::kLost); }

TEST(TrackingState, ARelocalisationWaitsForItsConfirmation) {
  EXPECT_EQ(NextTrackingState(S::kLost, E::kRelocalised), S::kConfirming);
}

TEST(TrackingState, TheNextTrackedFrameConfirmsIt) {
  EXPECT_EQ(NextTrackingState(S::kConfirming, E::kTracked), S::kTracking);
}

TEST(TrackingState, AWithdrawnRelocalisationIsLostAgain) {
  EXPECT_EQ(NextTrackingState(S::kConfirming, E::kWithdrawn), S::kLost);
}

TEST(TrackingState, EveryOtherPairIsNoTransition) {
  const S states[] = {S::kInitializing, S::kTracking, S::kLost, S::kConfirming};
  const E events[] = {E::kMapStarted, E::kMapLoaded, E::kTracked, E::kFailed, E::kRelocalised, E::kWithdrawn};
  int transitions = 0;
  for (S s : states)
    for (E e : events) transitions += NextTrackingState(s, e).has_value();
  EXPECT_EQ(transitions, 8);
  // Those an implementation could be tempted to allow.
  EXPECT_FALSE(NextTrackingState(S::kInitializing, E::kFailed));   // Frames the initialiser waits on.
  EXPECT_FALSE(NextTrackingState(S::kLost, E::kTracked));          // Lost: only relocalisation.
  EXPECT_FALSE(NextTrackingState(S::kConfirming, E::kFailed));     // Withdrawn first.
  EXPECT_FALSE(NextTrackingState(S::kConfirming, E::kRelocalised));
  EXPECT_FALSE(NextTrackingState(S::kTracking, E::kMapStarted));
  EXPECT_FALSE(NextTrackingState(S::kTracking, E::kMapLoaded));  // A map is loaded before any frame.
}

TEST(TrackingState, Names) {
  EXPECT_EQ(TrackingStateName(S::kInitializing), "initializing");
  EXPECT_EQ(TrackingStateName(S::kConfirming), "confirming");
}

}  // namespace
}  // namespace dsm
