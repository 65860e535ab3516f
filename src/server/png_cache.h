#pragma once
// A small thread-safe cache of encoded images by key (previews of points already seen,
// thumbnails, path strips): an LruCache behind a lock.
#include <cstddef>
#include <mutex>
#include <optional>
#include <string>

#include "server/lru_cache.h"

namespace matlas::server {

class PngCache {
public:
  explicit PngCache(std::size_t capacity) : items_(capacity) {}

  std::optional<std::string> get(const std::string& key);
  void put(const std::string& key, std::string value);
  std::size_t size() const;

private:
  mutable std::mutex mutex_;
  LruCache<std::string> items_;
};

}  // namespace matlas::server
