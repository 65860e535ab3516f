#pragma once
// The model's data in a distributed build (`mpirun -np P matlas build`): rank r writes the
// column-interleaved data of its share of the columns. Where that share starts in the model is
// known only once every rank has counted its kept columns (a column is dropped where any material
// lacks a measurement), so during the pass rank 0 appends its share to the model's temporary file
// as a single process does, and every other rank to a file of its own beside the model; then each
// of those ranks copies its file into the model's temporary file at its offset (in parallel: the
// ranges are disjoint) and removes it. Every rank also writes its slices of the mean and of the
// value-to-column map, so that no array of the data's length is gathered. Rank 0 renames the model into place once all have
// succeeded (manifold/build.cpp).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace matlas {

/// The target name of rank `rank`'s share of the data ("MODEL.rank-R"); the file written is an
/// AtomicFile temporary of it, never committed (removed on success, on error and on signals).
std::filesystem::path data_share_path(const std::filesystem::path& output, int rank);

/// Writes `bytes` bytes into the existing file `model` at `offset` and flushes them to disk (a
/// rank's slices of the mean and value_column tensors).
void write_into(const std::filesystem::path& model, std::uint64_t offset, const void* data, std::size_t bytes);

/// Reads `bytes` bytes of `model` at `offset` (rank 0 checksums the slices the ranks wrote).
std::vector<std::byte> read_from(const std::filesystem::path& model, std::uint64_t offset, std::size_t bytes);

/// Copies the `bytes` bytes of the file `share` into the existing file `model` at `offset` and
/// flushes them to disk (the model may sit on another machine's view of shared storage). Throws
/// matlas::Error naming the file on a short share, a read or a write failure.
void copy_share_into(const std::filesystem::path& share, std::uint64_t bytes, const std::filesystem::path& model,
                     std::uint64_t offset);

}  // namespace matlas
