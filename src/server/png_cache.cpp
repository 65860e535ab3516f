#include "server/png_cache.h"

namespace matlas::server {

std::optional<std::string> PngCache::get(const std::string& key) {
  std::lock_guard lock(mutex_);
  const auto it = index_.find(key);
  if (it == index_.end()) return std::nullopt;
  items_.splice(items_.begin(), items_, it->second);
  return it->second->second;
}

void PngCache::put(const std::string& key, std::string value) {
  if (capacity_ == 0) return;
  std::lock_guard lock(mutex_);
  if (const auto it = index_.find(key); it != index_.end()) {
    it->second->second = std::move(value);
    items_.splice(items_.begin(), items_, it->second);
    return;
  }
  items_.emplace_front(key, std::move(value));
  index_[key] = items_.begin();
  if (items_.size() > capacity_) {
    index_.erase(items_.back().first);
    items_.pop_back();
  }
}

std::size_t PngCache::size() const {
  std::lock_guard lock(mutex_);
  return items_.size();
}

}  // namespace matlas::server
