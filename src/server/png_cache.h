#pragma once
// A small thread-safe LRU cache of encoded images by key (previews of points already seen,
// thumbnails, path strips).
#include <cstddef>
#include <list>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>

namespace matlas::server {

class PngCache {
public:
  explicit PngCache(std::size_t capacity) : capacity_(capacity) {}

  std::optional<std::string> get(const std::string& key);
  void put(const std::string& key, std::string value);
  std::size_t size() const;

private:
  std::size_t capacity_;
  mutable std::mutex mutex_;
  std::list<std::pair<std::string, std::string>> items_;  // most recent first
  std::unordered_map<std::string, std::list<std::pair<std::string, std::string>>::iterator> index_;
};

}  // namespace matlas::server
