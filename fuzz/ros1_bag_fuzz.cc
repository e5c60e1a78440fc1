// SPDX-License-Identifier: MIT
// ROS 1 bags (bag/ros1_bag.h), read as fuzz_recording.h says.
#include "fuzz/fuzz_input.h"
#include "fuzz/fuzz_recording.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dsm::fuzz::FuzzRecording(dsm::fuzz::Scratch() / "fuzz.bag", data, size);
  return 0;
}
