#pragma once
// PreviewGenerations: per client address, how many preview requests it has sent. A refinement
// under way for a client (POST /api/preview/refine) watches its client's count through a
// SupersededSink and stops at the next row of its pass once the client asks for another preview:
// the pointer moved, and the pass would only delay the image the user now waits for.
#include <cstdint>
#include <mutex>
#include <string>
#include <unordered_map>

#include "core/progress.h"
#include "server/preview_source.h"

namespace matlas::server {

class PreviewGenerations {
public:
  std::uint64_t current(const std::string& client) const;
  /// Counts one preview request of `client`. At most 4096 clients are remembered; beyond that
  /// the counts start again (a refinement under way may then stop once without need).
  void advance(const std::string& client);

private:
  mutable std::mutex mutex_;
  std::unordered_map<std::string, std::uint64_t> counts_;
};

/// Throws PreviewSource::Interrupt from update() once `client` has sent a preview request after
/// `generation`.
class SupersededSink final : public ProgressSink {
public:
  SupersededSink(const PreviewGenerations& generations, std::string client, std::uint64_t generation)
      : generations_(generations), client_(std::move(client)), generation_(generation) {}
  void update(const std::string&, std::uint64_t, std::uint64_t) override {
    if (superseded()) throw PreviewSource::Interrupt{};
  }
  bool superseded() const { return generations_.current(client_) != generation_;
  }
  void message(const std::string&) override {}
  void finish(const std::string&) override {}

private:
  const PreviewGenerations& generations_;
  std::string client_;
  std::uint64_t generation_;
};

}  // namespace matlas::server
