#include "core/direct_appender.h"

#include <algorithm>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <exception>
#include <fcntl.h>
#include <mutex>
#include <sys/stat.h>
#include <thread>
#include <unistd.h>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/file_io.h"
#include "core/huge_pages.h"

namespace matlas {

// Outside the anonymous namespace: DirectAppender::State holds these (a member whose type has
// internal linkage draws -Wsubobject-linkage when files are compiled together as a unity build).
struct DirectBufferFree {
  void operator()(std::byte* p) const { std::free(p); }
};
using AlignedBuffer = std::unique_ptr<std::byte, DirectBufferFree>;

namespace {

AlignedBuffer aligned_buffer() {
  return AlignedBuffer(static_cast<std::byte*>(allocate_huge_pages(DirectAppender::kBufferBytes, DirectAppender::kAlignment)));
}

}  // namespace

struct DirectAppender::State {
  std::filesystem::path path;
  int fd = -1;
  std::uint64_t next_offset = 0;  ///< file offset of the buffer being filled
  int filling = 0;                ///< index of the buffer being filled
  std::size_t filled = 0;         ///< bytes staged in it

  // The writer thread writes the queued buffers in order while others fill; everything below is
  // guarded by `mutex` (buffers grows under it: the writer reads an address there).
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<AlignedBuffer> buffers;             ///< allocated as needed, at most kMaxBuffers
  std::vector<int> idle;                          ///< buffers free to fill
  std::deque<std::pair<int, std::uint64_t>> queue;  ///< full buffers and their offsets, to write in order
  bool writing = false, stop = false;
  std::exception_ptr failure;
  std::thread thread;

  void run() {
    std::unique_lock lock(mutex);
    for (;;) {
      changed.wait(lock, [&] { return stop || !queue.empty(); });
      if (stop) return;
      const auto [b, offset] = queue.front();
      queue.pop_front();
      const std::byte* data = buffers[static_cast<std::size_t>(b)].get();
      const bool skip = static_cast<bool>(failure);  // after a failure, buffers are only recycled
      writing = true;
      lock.unlock();
      std::exception_ptr error;
      if (!skip) {
        try {
          write_all_at(fd, path, data, kBufferBytes, offset);
        } catch (...) {
          error = std::current_exception();
        }
      }
      lock.lock();
      if (error && !failure) failure = error;
      idle.push_back(b);
      writing = false;
      changed.notify_all();
    }
  }

  /// Queues the buffer being filled and starts filling another: an idle one, a new one while
  /// fewer than kMaxBuffers exist, else the first the writer frees. Rethrows a write failure.
  void submit_full_buffer() {
    std::unique_lock lock(mutex);
    if (failure) std::rethrow_exception(failure);
    queue.emplace_back(filling, next_offset);
    changed.notify_all();
    next_offset += kBufferBytes;
    filled = 0;
    if (idle.empty() && buffers.size() < kMaxBuffers) {
      buffers.push_back(aligned_buffer());
      filling = static_cast<int>(buffers.size()) - 1;
      return;
    }
    changed.wait(lock, [&] { return !idle.empty(); });
    if (failure) std::rethrow_exception(failure);
    filling = idle.back();
    idle.pop_back();
  }
};

std::unique_ptr<DirectAppender> DirectAppender::open(const std::filesystem::path& path, std::uint64_t offset,
                                                     int same_file_as) {
  if (offset % kAlignment != 0) throw Error("DirectAppender: unaligned start offset (internal error)");
  // Reopened by name: never through a symlink (O_NOFOLLOW), and only if the name still holds the
  // caller's file (a name swapped for another file since would be written instead).
  const int fd = ::open(path.c_str(), O_WRONLY | O_DIRECT | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return nullptr;  // e.g. tmpfs: EINVAL
  if (same_file_as >= 0) {
    struct stat mine {}, theirs {};
    if (::fstat(fd, &theirs) != 0 || ::fstat(same_file_as, &mine) != 0 || mine.st_dev != theirs.st_dev ||
        mine.st_ino != theirs.st_ino) {
      ::close(fd);
      return nullptr;  // ordinary writes through the caller's descriptor
    }
  }
  auto state = std::make_unique<State>();
  state->path = path;
  state->fd = fd;
  state->next_offset = offset;
  state->buffers.push_back(aligned_buffer());
  State* s = state.get();
  state->thread = std::thread([s] { s->run(); });
  return std::unique_ptr<DirectAppender>(new DirectAppender(std::move(state)));
}

DirectAppender::DirectAppender(std::unique_ptr<State> state) : state_(std::move(state)) {}

DirectAppender::~DirectAppender() {
  {
    std::lock_guard lock(state_->mutex);
    state_->stop = true;
  }
  state_->changed.notify_all();
  state_->thread.join();
  ::close(state_->fd);
}

void DirectAppender::append(const void* data, std::size_t bytes) {
  State& s = *state_;
  const auto* p = static_cast<const std::byte*>(data);
  while (bytes > 0) {
    const std::size_t n = std::min(bytes, kBufferBytes - s.filled);
    std::memcpy(s.buffers[static_cast<std::size_t>(s.filling)].get() + s.filled, p, n);
    s.filled += n;
    p += n;
    bytes -= n;
    if (s.filled == kBufferBytes) s.submit_full_buffer();
  }
}

std::span<const std::byte> DirectAppender::finish() {
  State& s = *state_;
  std::unique_lock lock(s.mutex);
  s.changed.wait(lock, [&] { return s.queue.empty() && !s.writing; });
  if (s.failure) std::rethrow_exception(s.failure);
  return {s.buffers[static_cast<std::size_t>(s.filling)].get(), s.filled};
}

std::uint64_t DirectAppender::tail_offset() const { return state_->next_offset; }

}  // namespace matlas
