#pragma once
// LruCache: values by key, the least recently used dropped beyond a capacity; pinned keys are
// never dropped. The one cache of the server's model services: PNGs of previews (PngCache),
// loaded preview bases, refinements at rest and their scenes (BasisPreviews, GiScenes). Not
// thread-safe: its owner holds its own lock.
#include <cstddef>
#include <list>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>

namespace matlas::server {

template <class Value>
class LruCache {
public:
  /// Keeps at most `capacity` values (pinned ones excepted); 0 keeps none.
  explicit LruCache(std::size_t capacity) : capacity_(capacity) {}

  /// The value of `key`, now the most recently used; nullptr when absent.
  Value* find(const std::string& key) {
    const auto it = index_.find(key);
    if (it == index_.end()) return nullptr;
    items_.splice(items_.begin(), items_, it->second);
    return &it->second->second;
  }
  /// The value of `key` without using it; nullptr when absent.
  const Value* peek(const std::string& key) const {
    const auto it = index_.find(key);
    return it == index_.end() ? nullptr : &it->second->second;
  }
  bool contains(const std::string& key) const { return index_.contains(key); }

  /// Stores `value` under `key` (replacing a value there, or keeping it when `keep_existing`),
  /// makes it the most recently used, then drops the least recently used values beyond the
  /// capacity (never a pinned key, never this one). Returns the value kept under `key`, or
  /// nullptr with a capacity of 0.
  Value* put(const std::string& key, Value value, bool keep_existing = false) {
    if (capacity_ == 0) return nullptr;
    if (const auto it = index_.find(key); it != index_.end()) {
      if (!keep_existing) it->second->second = std::move(value);
      items_.splice(items_.begin(), items_, it->second);
    } else {
      items_.emplace_front(key, std::move(value));
      index_[key] = items_.begin();
    }
    for (auto it = std::prev(items_.end()); items_.size() > capacity_ && it != items_.begin();) {
      const auto victim = it--;
      if (pinned_.contains(victim->first)) continue;
      index_.erase(victim->first);
      items_.erase(victim);
    }
    return &items_.front().second;
  }

  /// `key` is never dropped (whether or not it is stored yet).
  void pin(const std::string& key) { pinned_.insert(key); }
  std::size_t size() const { return items_.size(); }

private:
  std::size_t capacity_;
  std::list<std::pair<std::string, Value>> items_;  ///< most recently used first
  std::unordered_map<std::string, typename std::list<std::pair<std::string, Value>>::iterator> index_;
  std::set<std::string> pinned_;
};

}  // namespace matlas::server
