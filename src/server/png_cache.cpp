#include "server/png_cache.h"

namespace matlas::server {

std::optional<std::string> PngCache::get(const std::string& key) {
  std::lock_guard lock(mutex_);
  if (const std::string* value = items_.find(key)) return *value;
  return std::nullopt;
}

void PngCache::put(const std::string& key, std::string value) {
  std::lock_guard lock(mutex_);
  items_.put(key, std::move(value));
}

std::size_t PngCache::size() const {
  std::lock_guard lock(mutex_);
  return items_.size();
}

}  // namespace matlas::server
