#include "formats/mapped_file.h"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <mutex>
#include <string>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.h"
#include "core/file_io.h"
#include "formats/mapping_watch.h"

namespace matlas {

namespace fs = std::filesystem;

namespace {

// SIGBUS guard of the mappings. Fixed slots readable from the signal handler: begin/end of each
// mapping (0 when free) and its fault count.
constexpr int kGuardSlots = 256;
struct GuardSlot {
  std::atomic<std::uintptr_t> begin{0}, end{0};
  std::atomic<std::uint64_t> faults{0};
};
GuardSlot g_guard[kGuardSlots];
struct sigaction g_previous_sigbus {};
std::uintptr_t g_page_size = 4096;

void chain_previous(int sig, siginfo_t* info, void* context) {
  if (g_previous_sigbus.sa_flags & SA_SIGINFO) {
    if (g_previous_sigbus.sa_sigaction) {
      g_previous_sigbus.sa_sigaction(sig, info, context);
      return;
    }
  } else if (g_previous_sigbus.sa_handler != SIG_DFL && g_previous_sigbus.sa_handler != SIG_IGN &&
             g_previous_sigbus.sa_handler != nullptr) {
    g_previous_sigbus.sa_handler(sig);
    return;
  }
  // Default action: restore it and return; the faulting access repeats and ends the process.
  ::signal(SIGBUS, SIG_DFL);
}

void on_sigbus(int sig, siginfo_t* info, void* context) {
  const auto addr = reinterpret_cast<std::uintptr_t>(info->si_addr);
  for (auto& slot : g_guard) {
    const std::uintptr_t begin = slot.begin.load(std::memory_order_acquire);
    if (begin == 0 || addr < begin || addr >= slot.end.load(std::memory_order_acquire)) continue;
    const std::uintptr_t page = g_page_size;
    void* at = reinterpret_cast<void*>(addr & ~(page - 1));
    // A private page of zeros in place of the vanished one: the access is retried and succeeds.
    if (::mmap(at, page, PROT_READ, MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED, -1, 0) != MAP_FAILED) {
      slot.faults.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    break;
  }
  chain_previous(sig, info, context);
}

void install_sigbus_guard() {
  static std::once_flag once;
  std::call_once(once, [] {
    g_page_size = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
    struct sigaction sa {};
    sa.sa_sigaction = on_sigbus;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_SIGINFO | SA_NODEFER;
    ::sigaction(SIGBUS, &sa, &g_previous_sigbus);
  });
}

int guard_mapping(const void* data, std::size_t size) {
  install_sigbus_guard();
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  for (int i = 0; i < kGuardSlots; ++i) {
    std::uintptr_t expected = 0;
    if (g_guard[i].begin.load() != 0) continue;
    // Claim by setting end first (begin stays 0, so the handler ignores the slot until complete).
    if (!g_guard[i].end.compare_exchange_strong(expected, begin + size)) continue;
    g_guard[i].faults.store(0);
    g_guard[i].begin.store(begin, std::memory_order_release);
    return i;
  }
  return -1;  // more than kGuardSlots mappings: this one is unguarded
}

void unguard_mapping(int slot) {
  if (slot < 0) return;
  g_guard[slot].begin.store(0, std::memory_order_release);
  g_guard[slot].end.store(0, std::memory_order_release);
}

std::int64_t mtime_ns(const struct stat& st) {
  return static_cast<std::int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
}

}  // namespace

MappedFile::MappedFile(const fs::path& path) : path_(path) {
  const int fd = open_regular_file(path, "a model or safetensors file");
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    ::close(fd);
    throw file_error(path, "cannot stat");
  }
  size_ = static_cast<std::size_t>(st.st_size);
  device_ = static_cast<std::uint64_t>(st.st_dev);
  inode_ = static_cast<std::uint64_t>(st.st_ino);
  mtime_ns_ = mtime_ns(st);
  if (size_ > 0) {
    void* p = ::mmap(nullptr, size_, PROT_READ, MAP_SHARED, fd, 0);
    if (p == MAP_FAILED) {
      ::close(fd);
      throw file_error(path, std::string("cannot memory-map: ") + std::strerror(errno));
    }
    data_ = static_cast<const std::byte*>(p);
    slot_ = guard_mapping(data_, size_);
  }
  ::close(fd);
  detail::track_mapping(this);
}

MappedFile::~MappedFile() {
  detail::untrack_mapping(this);
  unguard_mapping(slot_);
  if (data_) ::munmap(const_cast<std::byte*>(data_), size_);
}

std::uint64_t MappedFile::faults() const {
  return slot_ >= 0 ? g_guard[slot_].faults.load(std::memory_order_relaxed) : 0;
}

MappedFile::DiskState MappedFile::disk_state() const {
  struct stat st {};
  if (::stat(path_.c_str(), &st) != 0) return DiskState::replaced;
  if (static_cast<std::uint64_t>(st.st_dev) != device_ || static_cast<std::uint64_t>(st.st_ino) != inode_)
    return DiskState::replaced;
  if (static_cast<std::size_t>(st.st_size) != size_ || mtime_ns(st) != mtime_ns_) return DiskState::modified;
  return DiskState::same;
}

}  // namespace matlas
