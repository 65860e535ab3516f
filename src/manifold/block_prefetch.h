#pragma once
// BlockPrefetch: a streaming pass's reads of a database larger than memory, ahead of the pass and
// around the page cache. I/O threads read each block of every file (core/direct_reader.h) into
// one of a few buffers, files in order, up to `slots` blocks ahead of the block the pass is done
// with; the pass takes each file's values when they have arrived and hands the block back when it
// has read all of them. The threads spend their time waiting for the device, not on the cores.
//
// It replaces ReadAhead (manifold/read_ahead.h) where the page cache cannot hold the database
// anyway: nothing is added to the cache, so nothing needs to be released from it, and the pass
// no longer waits on its reads (I/O wait 0-1 core-seconds per 1000-material build against 1-14:
// docs/BENCHMARKS.md, "Direct reads").
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "core/direct_reader.h"
#include "manifold/material_set.h"

namespace matlas {

class BlockPrefetch {
public:
  /// I/O threads (each waits for the device most of the time: several keep its queue full).
  static constexpr unsigned kThreads = 8;
  /// Memory for the buffers: as many blocks ahead as fit (at least 2, at most 8).
  static constexpr std::size_t kBudgetBytes = std::size_t{640} << 20;

  /// Blocks [first_block, end_block) of `step` values of every file of `set` (block b: values
  /// [b * step, min((b + 1) * step, set.value_count()))). The set must outlive the prefetch.
  BlockPrefetch(const MaterialSet& set, std::size_t step, std::size_t first_block, std::size_t end_block);
  /// Stops the I/O threads (the reads in progress end first).
  ~BlockPrefetch();
  BlockPrefetch(const BlockPrefetch&) = delete;
  BlockPrefetch& operator=(const BlockPrefetch&) = delete;

  /// Blocks held at once.
  std::size_t slots() const { return slots_; }

  /// Waits until file i's values of block b have been read and returns their stored bytes (4 bytes
  /// off the alignment of a double, after the files' 12-byte header: MerlFile::visit_bytes reads
  /// them), valid until done(b). Rethrows the read's error.
  const std::byte* bytes(std::size_t b, std::size_t i);
  /// The pass is done with block b (blocks are done in order): its buffer takes a later block.
  void done(std::size_t b);

private:
  void run();

  const MaterialSet& set_;
  const std::size_t step_, first_, end_, n_;
  std::size_t file_bytes_ = 0;  ///< buffer bytes per file and block
  std::size_t slots_ = 0;
  std::vector<DirectReader> readers_;
  std::unique_ptr<std::byte, void (*)(void*)> memory_{nullptr, nullptr};

  std::mutex mutex_;
  std::condition_variable arrived_, freed_;
  std::size_t next_item_ = 0;  ///< (b - first) * n + i of the next read to start
  std::size_t done_ = 0;       ///< blocks the pass is done with: reads may go up to done_ + slots_
  bool stopping_ = false;
  /// What a read left in a slot's buffer for one file.
  struct Arrival {
    std::size_t block = 0;          ///< the block whose values are there, + 1 (0: none yet)
    const std::byte* at = nullptr;  ///< where its values start
    std::exception_ptr error;       ///< the read's error, if it failed
  };
  std::vector<Arrival> arrivals_;  ///< per slot and file
  std::vector<std::thread> threads_;
};

}  // namespace matlas
