// SPDX-License-Identifier: MIT
// Shared test main: seeds the C random generator so that any test using it repeats exactly.
#include <cstdlib>

#include <gtest/gtest.h>

int main(int argc, char** argv) {
  std::srand(20201120);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
