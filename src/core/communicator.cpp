#include "core/communicator.h"

#include <algorithm>
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

std::pair<std::size_t, std::size_t> share_of(std::size_t items, int part, int parts) {
  MATLAS_CHECK(parts >= 1 && part >= 0 && part < parts, "a share of a split");
  const auto p = static_cast<std::size_t>(part), count = static_cast<std::size_t>(parts);
  const std::size_t base = items / count, extra = items % count;
  const std::size_t first = p * base + std::min(p, extra);
  return {first, first + base + (p < extra ? 1 : 0)};
}

}  // namespace matlas
