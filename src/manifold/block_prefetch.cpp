#include "manifold/block_prefetch.h"

#include <algorithm>
#include <cstdlib>

#include "core/check.h"
#include "core/file_io.h"
#include "core/huge_pages.h"

namespace matlas {

BlockPrefetch::BlockPrefetch(const MaterialSet& set, std::size_t step, std::size_t first_block, std::size_t end_block)
    : set_(set), step_(step), first_(first_block), end_(std::max(first_block, end_block)), n_(set.size()) {
  MATLAS_CHECK_GT(step_, std::size_t{0});
  // A block's bytes start at most kAlignment - 4 bytes into an aligned block (its values are 8
  // bytes each after the 12-byte header).
  file_bytes_ = DirectReader::span(DirectReader::kAlignment - 4, step_ * sizeof(double));
  slots_ = std::clamp<std::size_t>(kBudgetBytes / std::max<std::size_t>(1, n_ * file_bytes_), 2, 8);
  slots_ = std::max<std::size_t>(1, std::min(slots_, end_ - first_));
  // Huge pages: the direct reads pin the buffers' pages, 2 MiB at a time rather than 4 KiB.
  memory_ = {static_cast<std::byte*>(allocate_huge_pages(slots_ * n_ * file_bytes_, DirectReader::kAlignment)),
             std::free};
  allow_open_files(2 * n_ + 256);  // a second descriptor per file (MaterialSet::open asked for the first)
  readers_.reserve(n_);
  for (std::size_t i = 0; i < n_; ++i) readers_.push_back(set.file(i).direct_reader());
  arrivals_.resize(slots_ * n_);
  const unsigned threads = static_cast<unsigned>(std::min<std::size_t>(kThreads, (end_ - first_) * n_));
  threads_.reserve(threads);
  for (unsigned t = 0; t < threads; ++t) threads_.emplace_back([this] { run(); });
}

BlockPrefetch::~BlockPrefetch() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  freed_.notify_all();
  for (std::thread& t : threads_) t.join();
}

void BlockPrefetch::run() {
  const std::size_t items = (end_ - first_) * n_, total = set_.value_count();
  for (;;) {
    std::size_t item = 0;
    {
      std::unique_lock lock(mutex_);
      freed_.wait(lock, [&] { return stopping_ || next_item_ >= items || next_item_ / n_ < done_ + slots_; });
      if (stopping_ || next_item_ >= items) return;
      item = next_item_++;
    }
    const std::size_t b = first_ + item / n_, i = item % n_, k = (item / n_) % slots_ * n_ + i;
    const std::size_t first = b * step_, count = std::min(step_, total - first);
    const std::byte* at = nullptr;
    std::exception_ptr error;
    try {
      at = readers_[i].read(MerlFile::value_offset(first), count * sizeof(double), memory_.get() + k * file_bytes_);
    } catch (...) {
      error = std::current_exception();
    }
    {
      std::lock_guard lock(mutex_);
      arrivals_[k] = {b + 1, at, error};
    }
    arrived_.notify_all();
  }
}

const std::byte* BlockPrefetch::bytes(std::size_t b, std::size_t i) {
  MATLAS_CHECK(b >= first_ && b < end_ && i < n_, "a block and file of the prefetch");
  const std::size_t k = (b - first_) % slots_ * n_ + i;
  std::unique_lock lock(mutex_);
  MATLAS_CHECK(b - first_ >= done_ && b - first_ < done_ + slots_, "a block the prefetch holds");
  const Arrival& arrival = arrivals_[k];
  arrived_.wait(lock, [&] { return arrival.block == b + 1; });
  if (arrival.error) std::rethrow_exception(arrival.error);
  return arrival.at;
}

void BlockPrefetch::done(std::size_t b) {
  {
    std::lock_guard lock(mutex_);
    MATLAS_CHECK_EQ(b - first_, done_);
    ++done_;
  }
  freed_.notify_all();
}

}  // namespace matlas
