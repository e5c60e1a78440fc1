// SPDX-License-Identifier: MIT
// Programmer-error checks and the exception for bad user input.
//
//  DSM_CHECK(cond, msg)   always on: prints file:line and the message, then aborts.
//  DSM_DCHECK(cond, msg)  debug builds only (kernels and hot loops).
//  InputError             thrown for bad files, calibration or options; the message names the
//                         file or key and says what is wrong. The command line turns it into exit 2.
#pragma once

#include <stdexcept>
#include <string>

namespace dsm {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

[[noreturn]] void CheckFailed(const char* file, int line, const char* condition,
                              const std::string& message);

}  // namespace dsm

#define DSM_CHECK(cond, msg)                                 \
  do {                                                       \
    if (!(cond)) ::dsm::CheckFailed(__FILE__, __LINE__, #cond, (msg)); \
  } while (false)

#ifdef NDEBUG
#define DSM_DCHECK(cond, msg) \
  do {                        \
  } while (false)
#else
#define DSM_DCHECK(cond, msg) DSM_CHECK(cond, msg)
#endif
