#pragma once
// Communicator: what a pass split across processes needs from its peers, without naming the
// engine. A build run by `mpirun -np P matlas build` gives every rank (process) a contiguous share
// of the column blocks; the ranks then add up their partial sums, gather their pieces on rank 0
// and agree on errors through this interface. The library only sees this header: the MPI
// implementation lives in the command (cli/mpi_world.h, compiled only when MPI is found), and a
// single process uses serial_communicator(), for which every operation is the identity.
//
// Every operation is collective: every rank calls it, in the same order, with the same sizes
// where a size is given.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace matlas {

class Communicator {
public:
  virtual ~Communicator() = default;
  /// This process's rank, 0 <= rank() < size().
  virtual int rank() const = 0;
  virtual int size() const = 0;
  /// Element-wise sum over the ranks, in place, on every rank (MPI_Allreduce in double).
  virtual void sum(std::span<double> values) = 0;
  /// Element-wise sum of compensated values value[k] + low[k] over the ranks, in place, on every
  /// rank: each addition keeps its rounding error in low (TwoSum), so value + low is the exact
  /// sum to about 2^-100, whatever the order in which the ranks' values meet.
  virtual void sum_compensated(std::span<double> value, std::span<double> low) = 0;
  /// Every rank's value, in rank order, on every rank.
  virtual std::vector<std::uint64_t> all_gather(std::uint64_t value) = 0;
  /// The concatenation of every rank's bytes in rank order, on rank 0; empty on the others.
  virtual std::vector<std::byte> gather(std::span<const std::byte> bytes) = 0;
  /// Rank 0's text, on every rank.
  virtual void broadcast(std::string& text) = 0;
  /// Error agreement: every rank gives its error message ("" when it succeeded) and gets back
  /// the message of the lowest failing rank, prefixed with that rank ("" when none failed).
  /// Waits without spinning: a rank that finished its share early leaves the cores to the others.
  virtual std::string first_error(const std::string& message) = 0;

  bool is_root() const { return rank() == 0; }
};

/// The communicator of one process alone (rank 0 of 1).
Communicator& serial_communicator();

/// Runs `step` on this rank, then agrees with the others: when any rank failed, every rank
/// throws (this rank's own exception where it failed, else a matlas::Error with the lowest
/// failing rank's message), so that no rank is left waiting in a later collective.
void run_collectively(Communicator& comm, const std::function<void()>& step);

/// Every rank's byte arrays on rank 0, in rank order (rank 0's first, then rank 1's, ...); empty
/// on the other ranks. Gathered in rounds of one array per rank, so a message never holds more
/// than one array of each rank (a thousand images gather without a multi-gigabyte message).
/// Collective; ranks may hold different numbers of arrays.
std::vector<std::vector<std::byte>> gather_arrays(Communicator& comm, const std::vector<std::vector<std::byte>>& mine);

/// Every rank's byte arrays on every rank, in rank order (gather_arrays, then broadcast: at most
/// 2 GB in all). Collective.
std::vector<std::vector<std::byte>> all_gather_arrays(Communicator& comm, const std::vector<std::vector<std::byte>>& mine);

namespace detail {

/// gather(comm, arrays as bytes), back as arrays of T: the typed form of a byte-array collective.
template <class T, class Gather>
std::vector<std::vector<T>> gather_typed(Gather gather, Communicator& comm, const std::vector<std::vector<T>>& mine) {
  static_assert(std::is_trivially_copyable_v<T>);
  std::vector<std::vector<std::byte>> bytes;
  bytes.reserve(mine.size());
  for (const auto& a : mine) {
    const auto b = std::as_bytes(std::span<const T>(a));
    bytes.emplace_back(b.begin(), b.end());
  }
  std::vector<std::vector<T>> all;
  for (const auto& b : gather(comm, bytes)) {
    std::vector<T>& a = all.emplace_back(b.size() / sizeof(T));
    if (!b.empty()) std::memcpy(a.data(), b.data(), b.size());
  }
  return all;
}

}  // namespace detail

/// gather_arrays for arrays of a trivially copyable type.
template <class T>
std::vector<std::vector<T>> gather_arrays(Communicator& comm, const std::vector<std::vector<T>>& mine) {
  using Bytes = std::vector<std::vector<std::byte>>;
  return detail::gather_typed<T>(static_cast<Bytes (*)(Communicator&, const Bytes&)>(&gather_arrays), comm, mine);
}

/// all_gather_arrays for arrays of a trivially copyable type.
template <class T>
std::vector<std::vector<T>> all_gather_arrays(Communicator& comm, const std::vector<std::vector<T>>& mine) {
  using Bytes = std::vector<std::vector<std::byte>>;
  return detail::gather_typed<T>(static_cast<Bytes (*)(Communicator&, const Bytes&)>(&all_gather_arrays), comm, mine);
}

/// Rank `part`'s contiguous share [first, last) of `items` items split into `parts` nearly equal
/// shares (the first shares take one more item when they do not divide evenly).
std::pair<std::size_t, std::size_t> share_of(std::size_t items, int part, int parts);

}  // namespace matlas
