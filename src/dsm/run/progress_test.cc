// SPDX-License-Identifier: MIT
#include "dsm/run/progress.h"

#include <gtest/gtest.h>

namespace dsm {
namespace {

ProgressState State(int done) {
  ProgressState s;
  s.done = done;
  s.total = 600;
  s.elapsed_s = done / 40.0;  // 40 fps.
  s.recording_s = done / 20.0;
  s.keyframes = 34;
  s.points = 8123;
  s.state = "tracking";
  return s;
}

std::string Written(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string text;
  for (int c; (c = std::fgetc(f)) != EOF;) text += static_cast<char>(c);
  return text;
}

TEST(Progress, FormatsRateRealTimeFactorAndTimeLeft) {
  EXPECT_EQ(FormatProgress(State(120)),
            "frame 120/600 (20%)  40.0 fps  2.00x real time  34 keyframes  8123 points  tracking  0:12 left");
  ProgressState unknown_rate = State(120);
  unknown_rate.recording_s = 0.0;
  unknown_rate.total = 120 + 40 * 3725;  // 1 h 2 min 5 s left.
  const std::string text = FormatProgress(unknown_rate);
  EXPECT_EQ(text.find("real time"), std::string::npos) << text;
  EXPECT_NE(text.find("  tracking  1:02:05 left"), std::string::npos) << text;
  ProgressState last = State(600);
  EXPECT_EQ(FormatProgress(last).find("left"), std::string::npos);
}

TEST(Progress, PlainLinesAtTheIntervalWhenNotATerminal) {
  std::FILE* f = std::tmpfile();
  Progress progress(f, /*terminal=*/false, /*interval_s=*/3600.0);
  progress.Update(State(1));           // Too soon after the start.
  progress.Update(State(2), true);     // Forced.
  progress.Update(State(3));           // Too soon after the last.
  progress.Event("frame 3  tracking lost");
  progress.Finish();
  EXPECT_EQ(Written(f), FormatProgress(State(2)) + "\nframe 3  tracking lost\n");
  std::fclose(f);
}

TEST(Progress, ZeroIntervalPrintsEveryUpdate) {
  std::FILE* f = std::tmpfile();
  Progress progress(f, false, 0.0);
  progress.Update(State(1));
  progress.Update(State(2));
  EXPECT_EQ(Written(f), FormatProgress(State(1)) + "\n" + FormatProgress(State(2)) + "\n");
  std::fclose(f);
}

TEST(Progress, TerminalLineRedrawnInPlaceAndEventsAboveIt) {
  std::FILE* f = std::tmpfile();
  Progress progress(f, /*terminal=*/true, 0.0);
  progress.Update(State(1), true);
  progress.Event("frame 1  tracking lost");
  progress.Finish();
  const std::string line = FormatProgress(State(1));
  EXPECT_EQ(Written(f), "\r\033[K" + line + "\r\033[Kframe 1  tracking lost\n" + line + "\r\033[K");
  std::fclose(f);
}

TEST(Progress, NullOutputPrintsNothingButWarningsStillGoOut) {
  Progress progress(nullptr, false, 0.0);
  progress.Update(State(1), true);
  std::FILE* warnings = std::tmpfile();
  progress.Event("dsm: warning: x", warnings);
  EXPECT_EQ(Written(warnings), "dsm: warning: x\n");
  std::fclose(warnings);
}

}  // namespace
}  // namespace dsm
