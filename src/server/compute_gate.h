#pragma once
// ComputeGate: bounds how many requests do heavy work at once. Waiters are served first come,
// first served (so tail latency under load stays close to the mean), and give up after a timeout,
// which the server answers with 503 instead of blocking a connection forever.
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <list>
#include <mutex>

namespace matlas::server {

class ComputeGate {
public:
  explicit ComputeGate(int slots);
  ComputeGate(const ComputeGate&) = delete;
  ComputeGate& operator=(const ComputeGate&) = delete;

  /// A held slot; released on destruction.
  class Slot {
  public:
    Slot() = default;
    Slot(Slot&& other) noexcept : gate_(other.gate_) { other.gate_ = nullptr; }
    Slot& operator=(Slot&& other) noexcept;
    Slot(const Slot&) = delete;
    Slot& operator=(const Slot&) = delete;
    ~Slot() { release(); }
    explicit operator bool() const { return gate_ != nullptr; }
    void release();

  private:
    friend class ComputeGate;
    explicit Slot(ComputeGate* gate) : gate_(gate) {}
    ComputeGate* gate_ = nullptr;
  };

  /// Waits up to `timeout` for a slot; an empty Slot on timeout.
  Slot acquire(std::chrono::milliseconds timeout);

  int slots() const { return slots_; }
  /// Requests waiting now (for diagnostics and tests).
  std::size_t waiting() const;

private:
  struct Waiter {
    std::condition_variable cv;
    bool granted = false;
  };
  void release_one();

  int slots_;
  int free_;
  mutable std::mutex mutex_;
  std::list<Waiter*> queue_;
};

}  // namespace matlas::server
