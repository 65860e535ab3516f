#include "manifold/column_blocks.h"

#include <algorithm>
#include <future>

#include <xxhash.h>

namespace matlas {

namespace {

/// Reads columns [first, first + count) of every material into `block` (physical units) and
/// marks the kept columns.
void read_block(const MaterialSet& set, std::size_t first, std::size_t count, BlockMatrix& block,
                std::vector<std::uint8_t>& kept, std::vector<XXH3_state_t*>& hashers) {
  const std::size_t n = set.size(), bins = set.dims().bins();
  block.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(count));
  kept.assign(count, 1);
  for (std::size_t i = 0; i < n; ++i) {
    double* row = block.row(static_cast<Eigen::Index>(i)).data();
    std::uint8_t* keep = kept.data();
    // One pass per cache-resident chunk: hash the stored bytes, then scale to physical units
    // channel by channel into the block; a column is kept only if every material measures it.
    set.file(i).visit_values(first, count, [&](const double* chunk, std::size_t offset, std::size_t length) {
      if (!hashers.empty()) XXH3_64bits_update(hashers[i], chunk, length * sizeof(double));
      std::size_t j = 0;
      while (j < length) {
        const std::size_t channel = (first + offset + j) / bins;
        const std::size_t channel_end = std::min(length, (channel + 1) * bins - first - offset);
        const double scale = BrdfTable::kChannelScale[channel];
        for (; j < channel_end; ++j) {
          keep[offset + j] &= static_cast<std::uint8_t>(chunk[j] >= 0.0);
          row[offset + j] = chunk[j] * scale;
        }
      }
    });
  }
}

}  // namespace

void for_each_column_block(const MaterialSet& set, const std::function<void(const ColumnBlock&)>& visit,
                           const BlockOptions& options, ProgressSink& progress) {
  const std::size_t total = set.value_count();
  const std::size_t step = std::max<std::size_t>(1, options.block_columns);
  const std::size_t blocks = (total + step - 1) / step;
  ProgressTask task(progress, options.label, blocks);

  std::vector<XXH3_state_t*> hashers;
  struct HasherCleanup {
    std::vector<XXH3_state_t*>& states;
    ~HasherCleanup() {
      for (auto* s : states) XXH3_freeState(s);
    }
  } cleanup{hashers};
  if (options.hashes) {
    for (std::size_t i = 0; i < set.size(); ++i) {
      hashers.push_back(XXH3_createState());
      XXH3_64bits_reset(hashers.back());
    }
  }

  BlockMatrix buffers[2];
  std::vector<std::uint8_t> kept[2];
  auto start_read = [&](std::size_t b) {
    const std::size_t first = b * step, count = std::min(step, total - first);
    return std::async(std::launch::async, [&, b, first, count] {
      // Cold files: have the disk fetch the block after this one while this one is read.
      if (first + count < total)
        for (std::size_t i = 0; i < set.size(); ++i) set.file(i).prefetch(first + count, step);
      read_block(set, first, count, buffers[b % 2], kept[b % 2], hashers);
    });
  };
  std::future<void> pending = start_read(0);
  for (std::size_t b = 0; b < blocks; ++b) {
    pending.get();  // rethrows read errors
    if (b + 1 < blocks) pending = start_read(b + 1);
    const std::size_t first = b * step, count = std::min(step, total - first);
    try {
      visit(ColumnBlock{first, count, buffers[b % 2], kept[b % 2]});
    } catch (...) {
      if (pending.valid()) pending.wait();
      throw;
    }
    task.advance();
  }
  if (options.hashes) {
    options.hashes->clear();
    for (auto* h : hashers) options.hashes->push_back(XXH3_64bits_digest(h));
  }
}

}  // namespace matlas
