#include "core/atomic_file.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "core/direct_appender.h"
#include "core/file_io.h"
#include "core/error.h"

namespace matlas {

namespace fs = std::filesystem;

AtomicFile::AtomicFile(fs::path target) : target_(std::move(target)) {
  temp_ = target_;
  temp_ += ".tmp-" + std::to_string(::getpid());
  fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw file_error(target_, std::string("cannot create output file: ") + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
  direct_.reset();
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) {
    std::error_code ec;
    fs::remove(temp_, ec);
  }
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
    direct_ = DirectAppender::open(temp_, position_);
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
  if (direct_) throw file_error(target_, "skip() after direct appends (internal error)");
  position_ += bytes;
}

void AtomicFile::commit() {
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
  std::error_code ec;
  if (!fs::exists(path, ec)) throw file_error(path, "no such file");
  if (fs::is_directory(path, ec)) throw file_error(path, "is a directory, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw file_error(path, std::string("cannot open: ") + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace matlas
