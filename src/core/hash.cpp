#include "core/hash.h"

#include <cstdio>
#include <new>

#include <xxhash.h>

namespace matlas {

std::uint64_t xxh3_64(const void* data, std::size_t bytes) { return XXH3_64bits(data, bytes); }

Xxh3Hasher::Xxh3Hasher() : state_(XXH3_createState()) {
  if (!state_) throw std::bad_alloc();
  XXH3_64bits_reset(state_);
}

Xxh3Hasher::~Xxh3Hasher() { XXH3_freeState(state_); }

void Xxh3Hasher::update(const void* data, std::size_t bytes) { XXH3_64bits_update(state_, data, bytes); }

std::uint64_t Xxh3Hasher::digest() const { return XXH3_64bits_digest(state_); }

std::string hex64(std::uint64_t h) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace matlas
