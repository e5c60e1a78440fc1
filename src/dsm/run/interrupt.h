// SPDX-License-Identifier: MIT
// SIGINT / SIGTERM during a run: the first one asks the run to stop after the current frame and
// write what it has (trajectories, stats with "interrupted": true, evaluation); the handler then
// falls back to the default, so a second one ends the process at once.
#pragma once

namespace dsm {

// Installs the handlers (idempotent).
void CatchInterrupts();
// The signal that asked to stop (SIGINT, SIGTERM), or 0.
int InterruptSignal();

}  // namespace dsm
