// SPDX-License-Identifier: MIT
// The front end's state machine: what the tracking side of a System does with the next frame.
//
//   state          event          next state
//   kInitializing  kMapStarted    kTracking
//   kInitializing  kMapLoaded     kLost        (a map from a map file: the camera is somewhere in it)
//   kTracking      kTracked       kTracking
//   kTracking      kFailed        kLost        (a lost episode opens)
//   kLost          kFailed        kLost
//   kLost          kRelocalised   kConfirming
//   kConfirming    kTracked       kTracking    (the relocalisation counts)
//   kConfirming    kWithdrawn     kLost
//
// kInitializing  frames go to the initialiser until two views start the map (tracking_start.cc).
// kTracking      each frame is aligned with the reference keyframe and judged by the quality test
//                (tracking_quality.h); a frame that passes may become a keyframe.
// kLost          the last frame failed the test: each frame with texture enough is aligned with
//                the keyframes most like it (Relocalise).
// kConfirming    the last frame was relocalised; its pose stands only once this frame, tracked from
//                it, passes the test too (kTracked: the relocalisation counts). A failure withdraws
//                it (kWithdrawn: the state before the relocalisation comes back, the frame is lost)
//                and the frame is tried against the map in turn. A relocalised frame makes no
//                keyframe and hands nothing to the mapping side.
#pragma once

#include <optional>
#include <string>

namespace dsm {

enum class TrackingState { kInitializing, kTracking, kLost, kConfirming };

enum class TrackingEvent {
  kMapStarted,    // The initialiser found two views.
  kMapLoaded,     // A map from a map file was taken up (System::RestoreMap), before any frame.
  kTracked,       // The frame passed the quality test against the reference.
  kFailed,        // The frame failed it (and, while lost, relocalisation failed).
  kRelocalised,   // A lost frame passed the test against a keyframe of the map.
  kWithdrawn,     // The relocalisation was not confirmed.
};

// The state after `event` in `state`; none when the event cannot happen there.
std::optional<TrackingState> NextTrackingState(TrackingState state, TrackingEvent event);

std::string TrackingStateName(TrackingState state);  // "initializing", "tracking", "lost", "confirming".

}  // namespace dsm
