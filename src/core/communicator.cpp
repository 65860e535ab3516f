#include "core/communicator.h"

#include <algorithm>
#include <cstring>
#include <exception>

#include "core/check.h"
#include "core/error.h"

namespace matlas {

namespace {

class SerialCommunicator final : public Communicator {
public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  void sum(std::span<double>) override {}
  void sum_compensated(std::span<double>, std::span<double>) override {}
  std::vector<std::uint64_t> all_gather(std::uint64_t value) override { return {value}; }
  std::vector<std::byte> gather(std::span<const std::byte> bytes) override { return {bytes.begin(), bytes.end()}; }
  void broadcast(std::string&) override {}
  std::string first_error(const std::string& message) override { return message; }
};

}  // namespace

Communicator& serial_communicator() {
  static SerialCommunicator serial;
  return serial;
}

void run_collectively(Communicator& comm, const std::function<void()>& step) {
  std::exception_ptr failure;
  std::string message;
  try {
    step();
  } catch (const std::exception& e) {
    failure = std::current_exception();
    message = e.what();
    if (message.empty()) message = "unknown error";
  }
  const std::string first = comm.first_error(message);
  if (failure) std::rethrow_exception(failure);
  if (!first.empty()) throw Error(first);
}

std::vector<std::vector<std::byte>> gather_arrays(Communicator& comm, const std::vector<std::vector<std::byte>>& mine) {
  if (comm.size() == 1) return mine;
  // Each round, every rank sends its next array after an 8-byte length (kNone when it has no
  // more), so rank 0 can cut the concatenation into the ranks' pieces.
  constexpr std::uint64_t kNone = ~std::uint64_t{0};
  std::uint64_t rounds = 0;
  for (const std::uint64_t count : comm.all_gather(mine.size())) rounds = std::max(rounds, count);
  std::vector<std::vector<std::vector<std::byte>>> per_rank(comm.is_root() ? static_cast<std::size_t>(comm.size()) : 0);
  std::vector<std::byte> message;
  for (std::size_t round = 0; round < rounds; ++round) {
    const bool have = round < mine.size();
    const std::uint64_t length = have ? mine[round].size() : kNone;
    message.resize(sizeof length + (have ? mine[round].size() : 0));
    std::memcpy(message.data(), &length, sizeof length);
    if (have && !mine[round].empty()) std::memcpy(message.data() + sizeof length, mine[round].data(), mine[round].size());
    const std::vector<std::byte> all = comm.gather(message);
    if (!comm.is_root()) continue;
    std::size_t at = 0;
    for (auto& arrays : per_rank) {
      MATLAS_CHECK_LE(at + sizeof(std::uint64_t), all.size());  // every rank sent its length
      std::uint64_t n = 0;
      std::memcpy(&n, all.data() + at, sizeof n);
      at += sizeof n;
      if (n == kNone) continue;
      MATLAS_CHECK_LE(at + n, all.size());
      arrays.emplace_back(all.begin() + static_cast<std::ptrdiff_t>(at), all.begin() + static_cast<std::ptrdiff_t>(at + n));
      at += n;
    }
    MATLAS_CHECK_EQ(at, all.size());
  }
  std::vector<std::vector<std::byte>> out;
  for (auto& arrays : per_rank)
    for (auto& a : arrays) out.push_back(std::move(a));
  return out;
}

std::vector<std::vector<std::byte>> all_gather_arrays(Communicator& comm, const std::vector<std::vector<std::byte>>& mine) {
  if (comm.size() == 1) return mine;
  // Rank 0 packs what it gathered as (8-byte length, bytes)... and broadcasts it.
  std::string packed;
  if (comm.is_root())
    for (const auto& a : gather_arrays(comm, mine)) {
      const std::uint64_t length = a.size();
      packed.append(reinterpret_cast<const char*>(&length), sizeof length);
      packed.append(reinterpret_cast<const char*>(a.data()), a.size());
    }
  else
    gather_arrays(comm, mine);
  comm.broadcast(packed);
  std::vector<std::vector<std::byte>> all;
  for (std::size_t at = 0; at < packed.size();) {
    std::uint64_t length = 0;
    MATLAS_CHECK_LE(at + sizeof length, packed.size());
    std::memcpy(&length, packed.data() + at, sizeof length);
    at += sizeof length;
    MATLAS_CHECK_LE(at + length, packed.size());
    const auto* first = reinterpret_cast<const std::byte*>(packed.data() + at);
    all.emplace_back(first, first + length);
    at += length;
  }
  return all;
}

std::pair<std::size_t, std::size_t> share_of(std::size_t items, int part, int parts) {
  MATLAS_CHECK(parts >= 1 && part >= 0 && part < parts, "a share of a split");
  const auto p = static_cast<std::size_t>(part), count = static_cast<std::size_t>(parts);
  const std::size_t base = items / count, extra = items % count;
  const std::size_t first = p * base + std::min(p, extra);
  return {first, first + base + (p < extra ? 1 : 0)};
}

}  // namespace matlas
