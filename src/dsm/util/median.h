// SPDX-License-Identifier: MIT
// The median of a sample: the element at index n / 2 of the sorted values (the upper one of the
// two middle values for even n), found with nth_element on a copy. The sample must not be empty.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace dsm {

template <typename T>
T Median(std::vector<T> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace dsm
