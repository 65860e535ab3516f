#include "core/atomic_file.h"

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <signal.h>
#include <unistd.h>

#include "core/direct_appender.h"
#include "core/file_io.h"
#include "core/error.h"

namespace matlas {

namespace fs = std::filesystem;

namespace {

// The temporary files of the live AtomicFiles, readable from a signal handler: fixed slots, each
// free (0), being filled (1) or published (2); the path is written before the slot is published
// (release) and read by the handler only when published (acquire).
constexpr int kSlots = 64;
constexpr std::size_t kPathBytes = 4096;
struct TempSlot {
  std::atomic<int> state{0};
  char path[kPathBytes];
};
TempSlot g_slots[kSlots];

int register_temporary(const fs::path& temp) {
  const std::string& text = temp.native();
  if (text.size() >= kPathBytes) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (!g_slots[i].state.compare_exchange_strong(expected, 1, std::memory_order_acquire)) continue;
    std::memcpy(g_slots[i].path, text.c_str(), text.size() + 1);
    g_slots[i].state.store(2, std::memory_order_release);
    return i;
  }
  return -1;  // more than kSlots outputs at once: no signal-time cleanup for this one
}

void unregister_temporary(int slot) {
  if (slot >= 0) g_slots[slot].state.store(0, std::memory_order_release);
}

void remove_temporaries_and_reraise(int sig) {
  for (auto& slot : g_slots)
    if (slot.state.load(std::memory_order_acquire) == 2) ::unlink(slot.path);
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

bool process_exists(long pid) {
  if (pid <= 0 || pid > 0x7fffffffL) return false;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH;
}

// The temporary names in use by the live AtomicFiles of this process: two outputs of one target
// at once get distinct names (TARGET.tmp-PID, TARGET.tmp-PID-2, ...), and a name found on disk
// that is not among these is not ours to keep.
std::mutex g_live_mutex;
std::set<std::string> g_live_temporaries;

fs::path claim_temporary_name(const fs::path& target) {
  const std::string base = target.native() + ".tmp-" + std::to_string(::getpid());
  const std::lock_guard lock(g_live_mutex);
  std::string name = base;
  for (int k = 2; g_live_temporaries.count(name); ++k) name = base + "-" + std::to_string(k);
  g_live_temporaries.insert(name);
  return name;
}

void release_temporary_name(const fs::path& temp) {
  const std::lock_guard lock(g_live_mutex);
  g_live_temporaries.erase(temp.native());
}

/// Creates `temp` as a new file, never opening what is already there: O_EXCL fails on any
/// existing name and O_NOFOLLOW on a symlink, so a link planted under the predictable name cannot
/// redirect the output onto another file. The name is not used by a live output of this process
/// (claim_temporary_name), so what holds it is a stale temporary of a killed process that had our
/// pid, or something planted: the name is removed (unlink removes a link, never what it points
/// to) and the creation retried. Returns the descriptor, or -1 with errno set.
int create_temporary(const fs::path& temp) {
  for (int attempt = 0; attempt < 16; ++attempt) {
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd >= 0 || errno != EEXIST) return fd;
    if (::unlink(temp.c_str()) != 0 && errno != ENOENT) return -1;
  }
  errno = EEXIST;  // something keeps recreating the name
  return -1;
}

// The checks every commit runs (CommitCheck), by registration number.
std::mutex g_checks_mutex;
std::map<std::uint64_t, std::function<void()>> g_commit_checks;
std::uint64_t g_next_check = 0;

/// PID or PID-K (an AtomicFile's temporary suffix): the pid, or -1 for any other text.
long temporary_pid(const std::string& suffix) {
  const std::size_t dash = suffix.find('-');
  const std::string digits = suffix.substr(0, dash);
  if (digits.empty() || digits.size() > 10 || digits.find_first_not_of("0123456789") != std::string::npos) return -1;
  if (dash != std::string::npos) {
    const std::string k = suffix.substr(dash + 1);
    if (k.empty() || k.size() > 10 || k.find_first_not_of("0123456789") != std::string::npos) return -1;
  }
  return std::stol(digits);
}

}  // namespace

CommitCheck::CommitCheck(std::function<void()> check) {
  const std::lock_guard lock(g_checks_mutex);
  id_ = g_next_check++;
  g_commit_checks.emplace(id_, std::move(check));
}

CommitCheck::~CommitCheck() {
  const std::lock_guard lock(g_checks_mutex);
  g_commit_checks.erase(id_);
}

void run_commit_checks() {
  const std::lock_guard lock(g_checks_mutex);
  for (const auto& [id, check] : g_commit_checks) check();
}

int remove_stale_temporaries(const fs::path& target) {
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const std::string prefix = target.filename().string() + ".tmp-";
  std::error_code ec;
  fs::directory_iterator it(dir, ec);
  if (ec) return 0;
  int removed = 0;
  for (; it != fs::directory_iterator(); it.increment(ec)) {
    if (ec) break;
    const std::string name = it->path().filename().string();
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
    const long pid = temporary_pid(name.substr(prefix.size()));
    if (pid < 0 || pid == static_cast<long>(::getpid()) || process_exists(pid)) continue;
    std::error_code rm;
    if (fs::remove(it->path(), rm)) ++removed;
  }
  return removed;
}

void remove_temporaries_on_signals() {
  struct sigaction sa {};
  sa.sa_handler = remove_temporaries_and_reraise;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(sig, &sa, nullptr);
}

AtomicFile::AtomicFile(fs::path target) : target_(std::move(target)) {
  if (target_.empty()) throw Error("the output file name is empty");
  std::error_code ec;
  if (fs::is_directory(target_, ec))
    throw file_error(target_, "is a folder; give the output a file name");
  remove_stale_temporaries(target_);
  temp_ = claim_temporary_name(target_);
  // Registered before it exists: a signal between creating the file and registering it would
  // leave it behind (the handler removing a name not yet created is harmless).
  slot_ = register_temporary(temp_);
  fd_ = create_temporary(temp_);
  if (fd_ < 0) {
    const int error = errno;
    unregister_temporary(slot_);
    release_temporary_name(temp_);
    throw file_error(target_, std::string("cannot create output file: ") + std::strerror(error));
  }
}

AtomicFile::~AtomicFile() {
  direct_.reset();
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) {
    std::error_code ec;
    fs::remove(temp_, ec);
  }
  unregister_temporary(slot_);
  release_temporary_name(temp_);
}

void AtomicFile::stream_appends_to_disk() { direct_wanted_ = true; }

void AtomicFile::write(const void* data, std::size_t bytes) {
  const auto* p = static_cast<const char*>(data);
  if (direct_wanted_ && !direct_) {
    // Ordinary writes up to the next aligned offset, direct ones from there on.
    const std::uint64_t aligned =
        (position_ + DirectAppender::kAlignment - 1) / DirectAppender::kAlignment * DirectAppender::kAlignment;
    const std::size_t head = static_cast<std::size_t>(std::min<std::uint64_t>(bytes, aligned - position_));
    write_all_at(fd_, target_, p, head, position_);
    position_ += head;
    p += head;
    bytes -= head;
    if (bytes == 0) return;
    direct_ = DirectAppender::open(temp_, position_, fd_);
    direct_wanted_ = static_cast<bool>(direct_);
  }
  if (direct_) direct_->append(p, bytes);
  else write_all_at(fd_, target_, p, bytes, position_);
  position_ += bytes;
}

void AtomicFile::write_at(std::uint64_t offset, const void* data, std::size_t bytes) {
  write_all_at(fd_, target_, data, bytes, offset);
}

void AtomicFile::skip(std::uint64_t bytes) {
  if (direct_) {
    // The direct appends stop before the hole (its bytes come from elsewhere, e.g. another rank
    // of a distributed build) and resume at the first aligned offset after it.
    const auto tail = direct_->finish();
    write_all_at(fd_, target_, tail.data(), tail.size(), direct_->tail_offset());
    direct_.reset();
  }
  position_ += bytes;
}

void AtomicFile::commit() {
  run_commit_checks();  // before anything is flushed or renamed: a refused output leaves nothing
  if (direct_) {
    const auto tail = direct_->finish();
    write_all_at(fd_, target_, tail.data(), tail.size(), direct_->tail_offset());
    direct_.reset();
  }
  if (::fsync(fd_) != 0) throw file_error(target_, std::string("flush failed: ") + std::strerror(errno));
  ::close(fd_);
  fd_ = -1;
  std::error_code ec;
  fs::rename(temp_, target_, ec);
  if (ec) throw file_error(target_, "cannot rename temporary file into place: " + ec.message());
  committed_ = true;
}

void write_file_atomic(const fs::path& target, const void* data, std::size_t bytes) {
  AtomicFile out(target);
  out.write(data, bytes);
  out.commit();
}

std::string read_file(const fs::path& path) {
  const int fd = open_regular_file(path, "a readable file");
  std::string text;
  char buf[1 << 16];
  for (;;) {
    const ssize_t got = ::read(fd, buf, sizeof buf);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) {
      const int err = errno;
      ::close(fd);
      throw file_error(path, std::string("read failed: ") + std::strerror(err));
    }
    if (got == 0) break;
    text.append(buf, static_cast<std::size_t>(got));
  }
  ::close(fd);
  return text;
}

}  // namespace matlas
