#include "manifold/read_ahead.h"

#include <algorithm>

#include <unistd.h>

#include "core/check.h"

namespace matlas {

ReadAhead::ReadAhead(Request issue, std::size_t begin, std::size_t end, std::size_t window, std::size_t chunk,
                     Request release)
    : issue_(std::move(issue)), release_(std::move(release)), begin_(begin), end_(std::max(begin, end)), window_(window), chunk_(chunk),
      position_(begin), issued_(begin), released_(begin) {
  MATLAS_CHECK(issue_ != nullptr, "a read-ahead request");
  MATLAS_CHECK(chunk_ > 0 && window_ >= chunk_, "a read-ahead window of at least one chunk");
  thread_ = std::thread([this] { run(); });
}

ReadAhead::~ReadAhead() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

std::size_t ReadAhead::target() const { return std::min(end_, position_ + window_); }

bool ReadAhead::release_due() const { return release_ && position_ - released_ >= chunk_; }

void ReadAhead::advance(std::size_t position) {
  {
    const std::lock_guard lock(mutex_);
    position = std::min(position, end_);  // nothing past the range is asked for or released
    if (position <= position_) return;
    position_ = position;
  }
  wake_.notify_one();
}

void ReadAhead::drain() {
  std::unique_lock lock(mutex_);
  done_.wait(lock, [this] { return stopping_ || (issued_ >= target() && !release_due()); });
}

std::size_t ReadAhead::issued() const {
  const std::lock_guard lock(mutex_);
  return issued_;
}

bool ReadAhead::worth_releasing(std::size_t bytes) {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return false;  // unknown: keep the kernel's own policy
  return bytes / static_cast<std::size_t>(page) > static_cast<std::size_t>(pages);
}

void ReadAhead::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stopping_ || issued_ < target() || release_due(); });
    if (stopping_) return;
    if (release_due()) {
      const std::size_t first = released_, count = position_ - released_;
      released_ = position_;
      lock.unlock();
      try {
        release_(first, count);
      } catch (...) {  // advisory, as the requests
      }
      lock.lock();
      if (issued_ >= target() && !release_due()) done_.notify_all();
      continue;
    }
    // The first request covers the whole window (the pass is about to read it); later ones a
    // chunk at a time as the pass moves on.
    const std::size_t first = issued_;
    const std::size_t count = first == begin_ ? target() - first : std::min(chunk_, target() - first);
    lock.unlock();
    bool failed = false;
    try {
      issue_(first, count);
    } catch (...) {  // advisory: the pass's own reads report what is wrong with the files
      failed = true;
    }
    lock.lock();
    issued_ = failed ? end_ : first + count;
    if (issued_ >= target() && !release_due()) done_.notify_all();
  }
}

}  // namespace matlas
