// SPDX-License-Identifier: MIT
#include "dsm/system/tracking_state.h"

namespace dsm {

std::optional<TrackingState> NextTrackingState(TrackingState state, TrackingEvent event) {
  using S = TrackingState;
  using E = TrackingEvent;
  switch (state) {
    case S::kInitializing:
      if (event == E::kMapStarted) return S::kTracking;
      if (event == E::kMapLoaded) return S::kLost;
      break;
    case S::kTracking:
      if (event == E::kTracked) return S::kTracking;
      if (event == E::kFailed) return S::kLost;
      break;
    case S::kLost:
      if (event == E::kFailed) return S::kLost;
      if (event == E::kRelocalised) return S::kConfirming;
      break;
    case S::kConfirming:
      if (event == E::kTracked) return S::kTracking;
      if (event == E::kWithdrawn) return S::kLost;
      break;
  }
  return std::nullopt;
}

std::string TrackingStateName(TrackingState state) {
  switch (state) {
    case TrackingState::kInitializing: return "initializing";
    case TrackingState::kTracking: return "tracking";
    case TrackingState::kLost: return "lost";
    case TrackingState::kConfirming: return "confirming";
  }
  return "?";
}

}  // namespace dsm
