#pragma once
// Progress reporting for long work. The library reports through a ProgressSink; the command line
// installs a terminal bar on stderr (silent when stderr is not a terminal). Library code never
// prints by itself.
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>

namespace matlas {

/// Receives (task label, done, total) updates and free-form status lines (e.g. optimiser steps).
class ProgressSink {
public:
  virtual ~ProgressSink() = default;
  virtual void update(const std::string& label, std::uint64_t done, std::uint64_t total) = 0;
  virtual void message(const std::string& line) = 0;
  virtual void finish(const std::string& label) = 0;
};

/// The sink that drops everything (the default for library calls).
ProgressSink& null_progress();

/// One line of the terminal bar: "label [#####.....]  45.0%  12.3 s, about 15 s left". The time
/// is the task's own (since its first update); the time left is extrapolated from the rate so far,
/// once at least 2 % is done and a second has passed.
std::string progress_line(const std::string& label, std::uint64_t done, std::uint64_t total, double seconds);

/// A text bar on stderr, redrawn at most 10 times a second; prints nothing unless stderr is a
/// terminal (or `force` is set). Messages go to stderr when `verbose`.
class TerminalProgress final : public ProgressSink {
public:
  explicit TerminalProgress(bool verbose = true, bool force = false);
  void update(const std::string& label, std::uint64_t done, std::uint64_t total) override;
  void message(const std::string& line) override;
  void finish(const std::string& label) override;

private:
  bool enabled_;
  bool verbose_;
  bool line_open_ = false;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point last_draw_{};
  std::string task_;                                     ///< the label of the task being drawn
  std::chrono::steady_clock::time_point task_start_{};  ///< its first update
};

/// Convenience: counts units of one task and forwards to a sink.
class ProgressTask {
public:
  ProgressTask(ProgressSink& sink, std::string label, std::uint64_t total)
      : sink_(sink), label_(std::move(label)), total_(total) {
    sink_.update(label_, 0, total_);
  }
  ~ProgressTask() { sink_.finish(label_); }
  ProgressTask(const ProgressTask&) = delete;
  ProgressTask& operator=(const ProgressTask&) = delete;
  void advance(std::uint64_t units = 1) {
    done_ += units;
    sink_.update(label_, done_, total_);
  }

private:
  ProgressSink& sink_;
  std::string label_;
  std::uint64_t total_;
  std::uint64_t done_ = 0;
};

}  // namespace matlas
