// SPDX-License-Identifier: MIT
#include "dsm/run/interrupt.h"

#include <csignal>

namespace dsm {

namespace {

volatile std::sig_atomic_t g_signal = 0;

extern "C" void OnInterrupt(int signal) {
  g_signal = signal;
  std::signal(signal, SIG_DFL);  // Async-signal-safe; the next one is not caught.
}

}  // namespace

void CatchInterrupts() {
  std::signal(SIGINT, OnInterrupt);
  std::signal(SIGTERM, OnInterrupt);
}

int InterruptSignal() { return g_signal; }

}  // namespace dsm
