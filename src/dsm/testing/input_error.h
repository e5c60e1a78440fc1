// SPDX-License-Identifier: MIT
// What a test of bad input asserts on: the message of the InputError an action throws.
#pragma once

#include <functional>
#include <string>

#include "dsm/util/check.h"

namespace dsm::testing {

// The message of the InputError that `f` throws, or "no error" when it throws none.
inline std::string MessageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace dsm::testing
