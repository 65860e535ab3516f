#include "manifold/block_rows.h"

#include <algorithm>
#include <cstring>
#include <new>

#if defined(__x86_64__)
#include <xxh_x86dispatch.h>
#endif

#include "brdf/brdf_table.h"
#include "core/simd_clones.h"

namespace matlas {

FileHashers::FileHashers(std::size_t n) : states_(n, nullptr) {
  for (XXH3_state_t*& s : states_) {
    s = XXH3_createState();
    if (!s) throw std::bad_alloc();
    XXH3_64bits_reset(s);
  }
}

FileHashers::~FileHashers() {
  for (XXH3_state_t* s : states_) XXH3_freeState(s);  // accepts null
}

std::vector<std::uint64_t> FileHashers::digests() const {
  std::vector<std::uint64_t> d;
  d.reserve(states_.size());
  for (const XXH3_state_t* s : states_) d.push_back(XXH3_64bits_digest(s));
  return d;
}

namespace {

/// xxHash's runtime-dispatched variant uses AVX2 or AVX-512 where the CPU has them (several
/// times the SSE2 default entry point); the hashes are the same.
void hash_update(XXH3_state_t* state, const void* data, std::size_t bytes) {
#if defined(__x86_64__)
  XXH3_64bits_update_dispatch(state, data, bytes);
#else
  XXH3_64bits_update(state, data, bytes);
#endif
}

/// The stored value at `in` (any alignment: a prefetched block's values are 4 bytes off).
inline double load(const std::byte* in) {
  double v;
  std::memcpy(&v, in, sizeof v);
  return v;
}

/// out = in * scale; keep &= (in >= 0); sum += out when sum is not null; `in` the stored bytes of
/// `length` values. Separate restrict pointers let the compiler vectorise.
MATLAS_SIMD_CLONES void scale_chunk(const std::byte* __restrict in, std::size_t length, double scale,
                                    double* __restrict out, std::uint8_t* __restrict keep, double* __restrict sum) {
  if (sum) {
    for (std::size_t j = 0; j < length; ++j) {
      const double v = load(in + j * sizeof(double)) * scale;
      out[j] = v;
      keep[j] &= static_cast<std::uint8_t>(v >= 0.0);
      sum[j] += v;
    }
  } else {
    for (std::size_t j = 0; j < length; ++j) {
      const double x = load(in + j * sizeof(double));
      out[j] = x * scale;
      keep[j] &= static_cast<std::uint8_t>(x >= 0.0);
    }
  }
}

}  // namespace

void read_block_rows(const MaterialSet& set, std::size_t first, std::size_t count, std::size_t row_begin,
                     std::size_t row_end, BlockMatrix& values, XXH3_state_t* const* hashers, RowGroupSums sums,
                     PrefetchedBlock prefetched) {
  const std::size_t bins = set.dims().bins();
  std::fill(sums.kept, sums.kept + count, std::uint8_t{1});
  if (sums.column_sums) std::fill(sums.column_sums, sums.column_sums + count, 0.0);
  for (std::size_t i = row_begin; i < row_end; ++i) {
    double* row = values.row(static_cast<Eigen::Index>(i)).data();
    const auto visit = [&](const std::byte* chunk, std::size_t offset, std::size_t length) {
      if (hashers) hash_update(hashers[i], chunk, length * sizeof(double));
      // Channel by channel, so that the scale is a constant of the inner loop.
      for (std::size_t j = 0; j < length;) {
        const std::size_t channel = (first + offset + j) / bins;
        const std::size_t end = std::min(length, (channel + 1) * bins - first - offset);
        const std::size_t at = offset + j;
        scale_chunk(chunk + j * sizeof(double), end - j, BrdfTable::kChannelScale[channel], row + at,
                    sums.kept + at, sums.column_sums ? sums.column_sums + at : nullptr);
        j = end;
      }
    };
    if (prefetched.prefetch) {
      set.file(i).visit_bytes(prefetched.prefetch->bytes(prefetched.block, i), first, count, visit);
    } else {
      set.file(i).visit_values(first, count, visit);
    }
  }
}

}  // namespace matlas
