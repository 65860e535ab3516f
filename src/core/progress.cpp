#include "core/progress.h"

#include <algorithm>
#include <cstdio>
#include <unistd.h>

namespace matlas {

namespace {
class NullProgress final : public ProgressSink {
public:
  void update(const std::string&, std::uint64_t, std::uint64_t) override {}
  void message(const std::string&) override {}
  void finish(const std::string&) override {}
};
}  // namespace

ProgressSink& null_progress() {
  static NullProgress sink;
  return sink;
}

namespace {

std::string duration_text(double seconds) {
  char buf[32];
  if (seconds < 60) std::snprintf(buf, sizeof buf, "%.0f s", seconds);
  else if (seconds < 3600) std::snprintf(buf, sizeof buf, "%d min %02d s", static_cast<int>(seconds / 60), static_cast<int>(seconds) % 60);
  else std::snprintf(buf, sizeof buf, "%d h %02d min", static_cast<int>(seconds / 3600), static_cast<int>(seconds / 60) % 60);
  return buf;
}

}  // namespace

std::string progress_line(const std::string& label, std::uint64_t done, std::uint64_t total, double seconds) {
  const double fraction = total ? std::min(1.0, static_cast<double>(done) / static_cast<double>(total)) : 0.0;
  constexpr int width = 30;
  const int filled = static_cast<int>(fraction * width + 0.5);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.resize(width, '.');
  char head[128];
  std::snprintf(head, sizeof head, "%-28.28s [%s] %5.1f%% %6.1f s", label.c_str(), bar.c_str(), 100.0 * fraction, seconds);
  std::string line = head;
  if (fraction >= 0.02 && fraction < 1.0 && seconds >= 1.0)
    line += ", about " + duration_text(seconds * (1.0 - fraction) / fraction) + " left";
  return line;
}

TerminalProgress::TerminalProgress(bool verbose, bool force)
    : enabled_(force || ::isatty(STDERR_FILENO)), verbose_(verbose) {}

void TerminalProgress::update(const std::string& label, std::uint64_t done, std::uint64_t total) {
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  if (label != task_) {
    task_ = label;
    task_start_ = now;
  }
  if (done != 0 && done < total && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  const double seconds = std::chrono::duration<double>(now - task_start_).count();
  // \x1b[K clears what a longer previous line left on the right.
  std::fprintf(stderr, "\r%s\x1b[K", progress_line(label, done, total, seconds).c_str());
  std::fflush(stderr);
  line_open_ = true;
}

void TerminalProgress::message(const std::string& line) {
  if (!verbose_) return;
  std::lock_guard lock(mutex_);
  if (line_open_) std::fputc('\n', stderr);
  line_open_ = false;
  std::fprintf(stderr, "%s\n", line.c_str());
}

void TerminalProgress::finish(const std::string&) {
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  if (line_open_) std::fputc('\n', stderr);
  line_open_ = false;
}

}  // namespace matlas
