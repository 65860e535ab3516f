#pragma once
// ComputeGate: bounds how many requests do heavy work at once, and shares the slots fairly
// between clients (their addresses).
//
// - A free slot goes to the waiting client that has used the gate least lately: each client's
//   use is the time it held slots, decaying with a half-life of `usage_half_life`. A client that
//   sends many requests, or one long one, therefore waits behind a client that sent one: a burst
//   from one address cannot starve the others. Among one client's waiters, first come first served.
// - A client may have at most `waiting_per_client` requests waiting: one more is refused at once
//   (kRefused), so that a flood from one address returns its connections instead of holding
//   them in the queue.
// - A waiter gives up after its timeout (kTimedOut): no request holds a connection longer than
//   the timeout waiting for a slot.
// Requests outside any client (an empty address: in-process callers) share one client, whose
// waiting requests are not capped.
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <list>
#include <map>
#include <mutex>
#include <string>

namespace matlas::server {

class ComputeGate {
public:
  struct Options {
    int slots = 1;
    int waiting_per_client = 4;
    std::chrono::milliseconds usage_half_life{10000};
  };
  explicit ComputeGate(int slots) : ComputeGate(Options{slots}) {}
  explicit ComputeGate(Options options);
  ComputeGate(const ComputeGate&) = delete;
  ComputeGate& operator=(const ComputeGate&) = delete;

  /// A held slot; released on destruction.
  class Slot {
  public:
    Slot() = default;
    Slot(Slot&& other) noexcept : gate_(other.gate_), client_(std::move(other.client_)), since_(other.since_) {
      other.gate_ = nullptr;
    }
    Slot& operator=(Slot&& other) noexcept;
    Slot(const Slot&) = delete;
    Slot& operator=(const Slot&) = delete;
    ~Slot() { release(); }
    explicit operator bool() const { return gate_ != nullptr; }
    void release();

  private:
    friend class ComputeGate;
    Slot(ComputeGate* gate, std::string client);
    ComputeGate* gate_ = nullptr;
    std::string client_;
    std::chrono::steady_clock::time_point since_{};
  };

  enum class Refusal { kNone, kTimedOut, kRefused };

  /// Waits up to `timeout` for a slot for `client`; an empty Slot when it timed out or when the
  /// client already has `waiting_per_client` requests waiting (`why` tells which).
  Slot acquire(std::chrono::milliseconds timeout, const std::string& client = {}, Refusal* why = nullptr);

  int slots() const { return options_.slots; }
  /// Requests waiting now (for diagnostics and tests).
  std::size_t waiting() const;

private:
  struct Waiter {
    std::string client;
    std::condition_variable cv;
    bool granted = false;
  };
  struct Client {
    int held = 0;
    int waiting = 0;
    double usage = 0.0;  ///< seconds of slot time, decayed to `stamp`
    std::chrono::steady_clock::time_point stamp{};
  };
  void release_one(const std::string& client, std::chrono::steady_clock::time_point since);
  /// The client's decayed usage now. Caller holds the mutex.
  double usage(Client& c, std::chrono::steady_clock::time_point now) const;
  /// Forgets clients with nothing held or waiting and negligible usage. Caller holds the mutex.
  void forget_idle(std::chrono::steady_clock::time_point now);

  Options options_;
  int free_;
  mutable std::mutex mutex_;
  std::list<Waiter*> queue_;
  std::map<std::string, Client> clients_;
};

/// The client (its address) of the request this thread is serving, for the gates' fair shares:
/// set by the server for the duration of each request. Empty outside a request.
const std::string& request_client();
void set_request_client(std::string address);

}  // namespace matlas::server
