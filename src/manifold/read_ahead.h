#pragma once
// ReadAhead: keeps a streaming pass's requests to the disk a window ahead of it, and, for a
// database larger than memory, lets the page cache drop what the pass has read, from a thread of
// its own.
//
// A pass reads every file of the database a block at a time. Asked for from that thread, the
// requests never hold a core of the pass's parallel regions (posix_fadvise can wait for a free
// slot in the device's queue). Behind the pass, a database larger than the machine's memory
// (1000 materials: 33 GB on a 23 GB machine) cannot stay in the page cache anyway, and without
// being told, the kernel evicts the least recently read pages: those of files the pass has yet to
// read, which it then reads from disk twice. Released as the pass moves on, the 1000-material
// build read 11 GB from disk instead of 23 GB (the disk's read counter; CHANGELOG.md,
// thirty-fifth session): half the traffic on shared storage, the same wall time on a fast local
// disk. The build's pass reads such a database around the page cache instead
// (manifold/block_prefetch.h); the evaluation's passes (column_blocks.h) come here.
//
// Whenever the pass moves on (advance), the thread releases what lies a chunk or more behind it,
// then issues what lies within `window` values ahead, `chunk` values at a time, in order, never
// past the end of the range. What a request or release does is the caller's (e.g.
// MerlFile::prefetch and MerlFile::release on every file of a MaterialSet): both are advisory,
// so it is never an error if they do nothing.
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>

namespace matlas {

class ReadAhead {
public:
  /// A request or release: values [first, first + count).
  using Request = std::function<void(std::size_t first, std::size_t count)>;

  /// issue(first, count): ask for values [first, first + count), called on the read-ahead thread
  /// in increasing order of `first`, covering [begin, end) piece by piece. window >= chunk > 0.
  /// The first request covers the window from `begin` at once. A request that throws ends the
  /// read-ahead (the pass's own reads report what is wrong).
  /// release(first, count), when given: values [first, first + count) behind the pass's position
  /// are no longer needed (called before the requests that follow).
  ReadAhead(Request issue, std::size_t begin, std::size_t end, std::size_t window, std::size_t chunk,
            Request release = nullptr);
  /// Stops after the request in progress (none is left half-issued) and joins the thread.
  ~ReadAhead();
  ReadAhead(const ReadAhead&) = delete;
  ReadAhead& operator=(const ReadAhead&) = delete;

  /// The pass now reads from `position` on: requests go out up to position + window.
  void advance(std::size_t position);
  /// Blocks until every request within the window of the last position has been issued and what
  /// lies a chunk or more behind it released (for tests).
  void drain();
  /// Values asked for so far: [begin, issued()).
  std::size_t issued() const;

  /// Whether a pass reading `bytes` should release what it has read: when they exceed the
  /// machine's physical memory, the page cache cannot keep them for a later run anyway, and the
  /// pages read first would otherwise push out cached ones the pass has yet to read.
  static bool worth_releasing(std::size_t bytes);

private:
  void run();
  std::size_t target() const;      ///< where issuing stops for now (mutex held)
  bool release_due() const;        ///< a chunk or more behind the pass to release (mutex held)

  const Request issue_, release_;
  const std::size_t begin_, end_, window_, chunk_;
  mutable std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::size_t position_, issued_, released_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace matlas
