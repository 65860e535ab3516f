#pragma once
// Atomic output: data goes to a temporary file beside the target, which is renamed over the
// target only once it is complete, so a crash or an error never leaves a half-written output.
//
// Temporary files are named TARGET.tmp-PID (TARGET.tmp-PID-K for a second output of the same
// target at once). They are created new, never opened where they exist (O_EXCL | O_NOFOLLOW: a
// symlink planted under the predictable name cannot redirect the output; what holds the name is
// removed first). They are removed when the AtomicFile is destroyed
// without commit, when the process is stopped by SIGINT, SIGTERM or SIGHUP (once
// remove_temporaries_on_signals() has been called, as the `matlas` command does), and, for a
// process that was killed outright, by the next AtomicFile of the same target: a TARGET.tmp-PID
// whose process no longer exists is stale and deleted.
//
// commit() first runs every live CommitCheck, so that an output computed from inputs that
// changed while they were read (a memory-mapped model truncated under the process) is refused
// before it replaces anything.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <string>

namespace matlas {

class DirectAppender;

class AtomicFile {
public:
  /// Opens "TARGET.tmp-PID" for writing (after deleting stale temporaries of TARGET left by dead
  /// processes); throws matlas::Error naming TARGET on failure, an empty name or a folder.
  explicit AtomicFile(std::filesystem::path target);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  /// Removes the temporary file unless commit() succeeded.
  ~AtomicFile();

  /// Appends at the end of what was appended so far.
  void write(const void* data, std::size_t bytes);
  void write(std::span<const std::byte> bytes) { write(bytes.data(), bytes.size()); }
  void write(const std::string& text) { write(text.data(), text.size()); }
  /// Writes at an absolute offset outside the appended range (e.g. into a hole left by skip()).
  void write_at(std::uint64_t offset, const void* data, std::size_t bytes);
  /// Advances the append position, leaving a hole to be filled with write_at() (or by another
  /// process writing into temporary()). After direct appends, the staged ones are written first.
  void skip(std::uint64_t bytes);
  /// Bytes appended (or skipped) so far.
  std::uint64_t position() const { return position_; }
  /// For large outputs written once: later appends go to disk with direct I/O from a background
  /// thread (core/direct_appender.h) instead of through the page cache. Falls back to ordinary
  /// writes where the file system has no direct I/O.
  void stream_appends_to_disk();
  /// Runs the live CommitChecks (one that throws refuses the output: the temporary file is
  /// removed and the target left as it was), then fsyncs and renames the temporary file to the
  /// target.
  void commit();

  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& temporary() const { return temp_; }

private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  int fd_ = -1;
  std::uint64_t position_ = 0;
  bool direct_wanted_ = false;
  std::unique_ptr<DirectAppender> direct_;
  bool committed_ = false;
  int slot_ = -1;  ///< entry in the signal-time cleanup registry, or -1
};

/// A condition every AtomicFile::commit() of the process checks while this object lives: `check`
/// throws (a matlas::Error naming the problem) to refuse the output. For inputs that can change
/// while they are read, e.g. the `matlas` command refuses every output once a memory-mapped input
/// was truncated under it. Checks run under a lock: a check must not create or destroy a
/// CommitCheck.
class CommitCheck {
public:
  explicit CommitCheck(std::function<void()> check);
  CommitCheck(const CommitCheck&) = delete;
  CommitCheck& operator=(const CommitCheck&) = delete;
  ~CommitCheck();

private:
  std::uint64_t id_ = 0;
};

/// Runs every live CommitCheck (what AtomicFile::commit() does first): for outputs that are not
/// files, such as a command's printed result.
void run_commit_checks();

/// Installs handlers for SIGINT, SIGTERM and SIGHUP that delete every temporary file of the live
/// AtomicFiles, then let the signal take its default action (the process ends as it would have).
void remove_temporaries_on_signals();

/// Deletes TARGET.tmp-PID (and TARGET.tmp-PID-K) files beside `target` whose process PID no
/// longer exists. Returns how many were removed. (Run by every AtomicFile; exposed for tests.)
int remove_stale_temporaries(const std::filesystem::path& target);

/// Writes a whole buffer atomically.
void write_file_atomic(const std::filesystem::path& target, const void* data, std::size_t bytes);
inline void write_file_atomic(const std::filesystem::path& target, const std::string& text) {
  write_file_atomic(target, text.data(), text.size());
}

/// Reads a whole file; throws matlas::Error naming the file if it is missing or unreadable.
std::string read_file(const std::filesystem::path& path);

}  // namespace matlas
