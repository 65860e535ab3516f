#include "server/preview_generations.h"

namespace matlas::server {

std::uint64_t PreviewGenerations::current(const std::string& client) const {
  std::lock_guard lock(mutex_);
  const auto it = counts_.find(client);
  return it == counts_.end() ? 0 : it->second;
}

void PreviewGenerations::advance(const std::string& client) {
  std::lock_guard lock(mutex_);
  if (counts_.size() >= 4096 && !counts_.contains(client)) counts_.clear();
  ++counts_[client];
}

}  // namespace matlas::server
