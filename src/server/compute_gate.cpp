#include "server/compute_gate.h"

#include <algorithm>

namespace matlas::server {

ComputeGate::ComputeGate(int slots) : slots_(std::max(1, slots)), free_(slots_) {}

ComputeGate::Slot& ComputeGate::Slot::operator=(Slot&& other) noexcept {
  if (this != &other) {
    release();
    gate_ = other.gate_;
    other.gate_ = nullptr;
  }
  return *this;
}

void ComputeGate::Slot::release() {
  if (gate_) gate_->release_one();
  gate_ = nullptr;
}

ComputeGate::Slot ComputeGate::acquire(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  if (free_ > 0 && queue_.empty()) {
    --free_;
    return Slot(this);
  }
  Waiter self;
  const auto it = queue_.insert(queue_.end(), &self);
  if (!self.cv.wait_for(lock, timeout, [&] { return self.granted; })) {
    queue_.erase(it);
    return Slot();
  }
  return Slot(this);  // release_one() handed its slot over and removed us from the queue
}

void ComputeGate::release_one() {
  std::lock_guard lock(mutex_);
  if (queue_.empty()) {
    ++free_;
    return;
  }
  Waiter* next = queue_.front();
  queue_.pop_front();
  next->granted = true;
  next->cv.notify_one();
}

std::size_t ComputeGate::waiting() const {
  std::lock_guard lock(mutex_);
  return queue_.size();
}

}  // namespace matlas::server
