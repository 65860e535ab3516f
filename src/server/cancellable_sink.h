#pragma once
// CancellableSink: forwards progress, and aborts the computation reporting it (by throwing
// Cancelled from update) once `stop` is set: how the servers' background workers stop a long
// render or trace when they are destroyed.
#include <atomic>
#include <string>

#include "core/progress.h"

namespace matlas::server {

struct Cancelled {};

class CancellableSink final : public ProgressSink {
public:
  CancellableSink(ProgressSink& inner, const std::atomic<bool>& stop) : inner_(inner), stop_(stop) {}
  void update(const std::string& label, std::uint64_t done, std::uint64_t total) override {
    if (stop_) throw Cancelled{};
    inner_.update(label, done, total);
  }
  void message(const std::string& line) override { inner_.message(line); }
  void finish(const std::string& label) override { inner_.finish(label); }

private:
  ProgressSink& inner_;
  const std::atomic<bool>& stop_;
};

}  // namespace matlas::server
