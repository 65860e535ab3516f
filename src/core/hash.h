#pragma once
// The one hash function of matlas: xxh3-64 (libxxhash). Used for the model's checksums and
// input-file digests, and for cache keys (image bases, demo models).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

struct XXH3_state_s;

namespace matlas {

/// xxh3-64 of a byte range.
std::uint64_t xxh3_64(const void* data, std::size_t bytes);
inline std::uint64_t xxh3_64(std::string_view bytes) { return xxh3_64(bytes.data(), bytes.size()); }

/// xxh3-64 of the concatenation of the ranges passed to update(), computed as they come.
class Xxh3Hasher {
public:
  Xxh3Hasher();
  ~Xxh3Hasher();
  Xxh3Hasher(const Xxh3Hasher&) = delete;
  Xxh3Hasher& operator=(const Xxh3Hasher&) = delete;
  void update(const void* data, std::size_t bytes);
  void update(std::string_view bytes) { update(bytes.data(), bytes.size()); }
  std::uint64_t digest() const;

private:
  XXH3_state_s* state_;
};

/// 16 lower-case hex digits.
std::string hex64(std::uint64_t h);

}  // namespace matlas
