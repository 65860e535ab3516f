#pragma once
// TempDir: a fresh folder under the system temporary directory, removed with its contents.
#include <filesystem>
#include <string>

namespace matlas::test {

class TempDir {
public:
  explicit TempDir(const std::string& prefix = "matlas-test");
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

private:
  std::filesystem::path path_;
};

}  // namespace matlas::test
