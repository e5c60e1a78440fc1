// SPDX-License-Identifier: MIT
#include "dsm/run/progress.h"

#include <algorithm>
#include <cmath>

namespace dsm {

namespace {

std::string Duration(double s) {
  const long total = std::lround(std::max(0.0, s));
  char text[32];
  if (total >= 3600) {
    std::snprintf(text, sizeof(text), "%ld:%02ld:%02ld", total / 3600, total / 60 % 60, total % 60);
  } else {
    std::snprintf(text, sizeof(text), "%ld:%02ld", total / 60, total % 60);
  }
  return text;
}

}  // namespace

std::string FormatProgress(const ProgressState& s) {
  const double fps = s.elapsed_s > 0.0 ? s.done / s.elapsed_s : 0.0;
  char text[256];
  // A live camera's frames have no total.
  int n = s.total > 0 ? std::snprintf(text, sizeof(text), "frame %d/%d (%d%%)  %.1f fps", s.done, s.total,
                                      100 * s.done / s.total, fps)
                      : std::snprintf(text, sizeof(text), "frame %d  %.1f fps", s.done, fps);
  if (s.recording_s > 0.0 && s.elapsed_s > 0.0) {
    n += std::snprintf(text + n, sizeof(text) - n, "  %.2fx real time", s.recording_s / s.elapsed_s);
  }
  n += std::snprintf(text + n, sizeof(text) - n, "  %d keyframes  %d points  %s", s.keyframes, s.points,
                     s.state.c_str());
  if (fps > 0.0 && s.done < s.total) {
    std::snprintf(text + n, sizeof(text) - n, "  %s left", Duration((s.total - s.done) / fps).c_str());
  }
  return text;
}

Progress::Progress(std::FILE* out, bool terminal, double interval_s)
    : out_(out), terminal_(terminal), interval_s_(terminal ? 0.2 : interval_s), last_(std::chrono::steady_clock::now()) {}

void Progress::Update(const ProgressState& s, bool force) {
  if (!out_) return;
  const auto now = std::chrono::steady_clock::now();
  if (!force && std::chrono::duration<double>(now - last_).count() < interval_s_) return;
  last_ = now;
  text_ = FormatProgress(s);
  if (terminal_) {
    std::fprintf(out_, "\r\033[K%s", text_.c_str());  // Carriage return, erase the line, redraw.
    shown_ = true;
  } else {
    std::fprintf(out_, "%s\n", text_.c_str());
  }
  std::fflush(out_);
}

void Progress::Event(const std::string& line, std::FILE* to) {
  if (!out_ && !to) return;
  if (out_) Clear();
  std::fprintf(to ? to : out_, "%s\n", line.c_str());
  if (to) std::fflush(to);
  if (!out_) return;
  if (terminal_ && !text_.empty()) {
    std::fprintf(out_, "%s", text_.c_str());
    shown_ = true;
  }
  std::fflush(out_);
}

void Progress::Finish() {
  if (!out_) return;
  Clear();
  std::fflush(out_);
}

void Progress::Clear() {
  if (shown_) std::fprintf(out_, "\r\033[K");
  shown_ = false;
}

}  // namespace dsm
