#include "server/compute_gate.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace matlas::server {

namespace {

using Clock = std::chrono::steady_clock;

thread_local std::string t_request_client;

}  // namespace

const std::string& request_client() { return t_request_client; }
void set_request_client(std::string address) { t_request_client = std::move(address); }

ComputeGate::ComputeGate(Options options) : options_(options) {
  options_.slots = std::max(1, options_.slots);
  options_.waiting_per_client = std::max(1, options_.waiting_per_client);
  free_ = options_.slots;
}

ComputeGate::Slot::Slot(ComputeGate* gate, std::string client)
    : gate_(gate), client_(std::move(client)), since_(Clock::now()) {}

ComputeGate::Slot& ComputeGate::Slot::operator=(Slot&& other) noexcept {
  if (this != &other) {
    release();
    gate_ = other.gate_;
    client_ = std::move(other.client_);
    since_ = other.since_;
    other.gate_ = nullptr;
  }
  return *this;
}

void ComputeGate::Slot::release() {
  if (gate_) gate_->release_one(client_, since_);
  gate_ = nullptr;
}

double ComputeGate::usage(Client& c, Clock::time_point now) const {
  const double elapsed = std::chrono::duration<double>(now - c.stamp).count();
  const double half_life = std::max(1e-3, std::chrono::duration<double>(options_.usage_half_life).count());
  c.usage *= std::exp2(-std::max(0.0, elapsed) / half_life);
  c.stamp = now;
  return c.usage;
}

void ComputeGate::forget_idle(Clock::time_point now) {
  for (auto it = clients_.begin(); it != clients_.end();) {
    Client& c = it->second;
    if (c.held == 0 && c.waiting == 0 && usage(c, now) < 1e-3) it = clients_.erase(it);
    else ++it;
  }
}

ComputeGate::Slot ComputeGate::acquire(std::chrono::milliseconds timeout, const std::string& client, Refusal* why) {
  if (why) *why = Refusal::kNone;
  std::unique_lock lock(mutex_);
  Client& c = clients_[client];
  if (free_ > 0 && queue_.empty()) {
    --free_;
    ++c.held;
    return Slot(this, client);
  }
  if (!client.empty() && c.waiting >= options_.waiting_per_client) {
    if (why) *why = Refusal::kRefused;
    return Slot();
  }
  Waiter self;
  self.client = client;
  ++c.waiting;
  const auto it = queue_.insert(queue_.end(), &self);
  const bool granted = self.cv.wait_for(lock, timeout, [&] { return self.granted; });
  --c.waiting;  // `c` is still there: forget_idle() keeps clients with waiters
  if (!granted) {
    queue_.erase(it);
    if (why) *why = Refusal::kTimedOut;
    return Slot();
  }
  return Slot(this, client);  // release_one() handed its slot over, counted it and removed us from the queue
}

void ComputeGate::release_one(const std::string& client, Clock::time_point since) {
  std::lock_guard lock(mutex_);
  const Clock::time_point now = Clock::now();
  if (const auto it = clients_.find(client); it != clients_.end()) {
    Client& c = it->second;
    --c.held;
    usage(c, now);
    c.usage += std::chrono::duration<double>(now - since).count();
  }
  if (queue_.empty()) {
    ++free_;
    forget_idle(now);
    return;
  }
  // The waiter of the client holding fewest slots, then with the least recent use; the queue is in
  // arrival order, so ties go to the earliest.
  auto best = queue_.end();
  int best_held = 0;
  double best_usage = 0.0;
  for (auto it = queue_.begin(); it != queue_.end(); ++it) {
    Client& c = clients_[(*it)->client];
    const int held = c.held;
    const double u = usage(c, now);
    if (best == queue_.end() || held < best_held || (held == best_held && u < best_usage)) {
      best = it;
      best_held = held;
      best_usage = u;
    }
  }
  Waiter* next = *best;
  queue_.erase(best);
  ++clients_[next->client].held;
  next->granted = true;
  next->cv.notify_one();
}

std::size_t ComputeGate::waiting() const {
  std::lock_guard lock(mutex_);
  return queue_.size();
}

}  // namespace matlas::server
