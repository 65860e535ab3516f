#include "manifold/column_blocks.h"

#include <algorithm>
#include <future>

#include "manifold/block_rows.h"
#include "manifold/read_ahead.h"

namespace matlas {

namespace {

/// Reads columns [first, first + count) of every material into `block` (physical units) and
/// marks the kept columns.
void read_block(const MaterialSet& set, std::size_t first, std::size_t count, BlockMatrix& block,
                std::vector<std::uint8_t>& kept) {
  block.resize(static_cast<Eigen::Index>(set.size()), static_cast<Eigen::Index>(count));
  kept.resize(count);
  read_block_rows(set, first, count, 0, set.size(), block, nullptr,
                  {nullptr, kept.data()});
}

}  // namespace

void for_each_column_block(const MaterialSet& set, const std::function<void(const ColumnBlock&)>& visit,
                           const BlockOptions& options, ProgressSink& progress) {
  const std::size_t total = std::min(set.value_count(), options.end_value);
  const std::size_t begin = std::min(options.first_value, total);
  const std::size_t step = std::max<std::size_t>(1, options.block_columns);
  const std::size_t blocks = (total - begin + step - 1) / step;
  ProgressTask task(progress, options.label, blocks);
  if (blocks == 0) return;

  // Cold files: the disk fetches the two blocks after the one being read; a database larger than
  // memory leaves the page cache as it is read (read_ahead.h).
  const bool release = ReadAhead::worth_releasing(set.size() * (total - begin) * sizeof(double));
  ReadAhead ahead([&set](std::size_t first, std::size_t count) { set.prefetch(first, count); }, begin, total,
                  3 * step, step,
                  release ? ReadAhead::Request([&set](std::size_t first, std::size_t count) { set.release(first, count); })
                          : nullptr);
  BlockMatrix buffers[2];
  std::vector<std::uint8_t> kept[2];
  auto start_read = [&](std::size_t b) {
    const std::size_t first = begin + b * step, count = std::min(step, total - first);
    ahead.advance(first);
    return std::async(std::launch::async, [&, b, first, count] {
      read_block(set, first, count, buffers[b % 2], kept[b % 2]);
    });
  };
  std::future<void> pending = start_read(0);
  for (std::size_t b = 0; b < blocks; ++b) {
    pending.get();  // rethrows read errors
    if (b + 1 < blocks) pending = start_read(b + 1);
    const std::size_t first = begin + b * step, count = std::min(step, total - first);
    try {
      visit(ColumnBlock{first, count, buffers[b % 2], kept[b % 2]});
    } catch (...) {
      if (pending.valid()) pending.wait();
      throw;
    }
    task.advance();
  }
}

}  // namespace matlas
