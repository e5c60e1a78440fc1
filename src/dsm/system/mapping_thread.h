// SPDX-License-Identifier: MIT
// The mapping side of the two threads of the paper (section III): a worker that runs the jobs
// handed to it one at a time, in the order they were handed over, on its own thread and in its
// own TBB arena (so a tracking thread waiting in a parallel loop never runs mapping work).
//
// All state shared between the two threads goes through this class, under its one mutex: the job
// queue, the number of keyframe jobs not finished yet, and the first error a job threw (rethrown to
// the submitting thread by Submit / WaitUntilIdle / WaitForKeyframes).
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace dsm {

class MappingThread {
 public:
  using Job = std::function<void()>;
  MappingThread();
  ~MappingThread();  // Finishes the queued jobs, then joins.
  MappingThread(const MappingThread&) = delete;
  MappingThread& operator=(const MappingThread&) = delete;

  // Queues a job, and `then` (if any) right behind it; `keyframe` jobs are counted until they
  // finish (pending), and until their `then` finishes too (unsettled).
  void Submit(Job job, bool keyframe, Job then = nullptr);
  // Keyframe jobs queued or running.
  int KeyframesPending() const;
  // Keyframe jobs whose job or `then` is queued or running.
  int KeyframesUnsettled() const;
  // Blocks until no keyframe job is queued or running.
  void WaitForKeyframes();
  // Blocks until every keyframe is settled, but no later than `deadline`; true when none is left.
  bool WaitForSettledKeyframesUntil(std::chrono::steady_clock::time_point deadline);
  // Blocks until every job handed over has finished. `urgent`: the caller needs the mapping side
  // idle now (a relocalisation); long jobs ask Urgent() and stop early.
  void WaitUntilIdle(bool urgent = false);
  // Someone waits in WaitUntilIdle(urgent).
  bool Urgent() const;
  // The largest number of keyframe jobs queued or running at once.
  int KeyframeQueueMax() const;

 private:
  void Loop();
  void RethrowLocked();

  mutable std::mutex mutex_;
  std::condition_variable work_, done_;
  struct Entry {
    Job job;
    bool keyframe;
    bool settles;  // The last of a keyframe's jobs.
  };
  std::deque<Entry> queue_;
  bool running_ = false, stop_ = false;
  int keyframes_pending_ = 0, keyframes_unsettled_ = 0, keyframe_queue_max_ = 0;
  int urgent_waiters_ = 0;
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace dsm
