#include "core/progress.h"

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

TerminalProgress::TerminalProgress(bool verbose, bool force)
    : enabled_(force || ::isatty(STDERR_FILENO)), verbose_(verbose) {}

void TerminalProgress::update(const std::string& label, std::uint64_t done, std::uint64_t total) {
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  if (done != 0 && done < total && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  const double fraction = total ? static_cast<double>(done) / static_cast<double>(total) : 0.0;
  constexpr int width = 30;
  const int filled = static_cast<int>(fraction * width + 0.5);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.resize(width, '.');
  const double seconds = std::chrono::duration<double>(now - start_).count();
  std::fprintf(stderr, "\r%-28.28s [%s] %5.1f%% %6.1fs", label.c_str(), bar.c_str(),
               100.0 * fraction, seconds);
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
