#include "cli/mpi_world.h"

#include <algorithm>
#include <chrono>
#include <climits>
#include <thread>

#include <mpi.h>

#include "cli/print.h"
#include "cli/run.h"
#include "cli/world.h"
#include "core/check.h"

namespace matlas::cli {

namespace {

/// Elements per MPI call (counts are int).
constexpr std::size_t kMaxCount = std::size_t{1} << 30;

/// Waits for a non-blocking operation, sleeping between tests: a rank that reached an agreement
/// early (its share done) must not spin on a core the others still compute on.
void wait_gently(MPI_Request& request) {
  int done = 0;
  auto pause = std::chrono::microseconds(50);
  for (MPI_Test(&request, &done, MPI_STATUS_IGNORE); !done; MPI_Test(&request, &done, MPI_STATUS_IGNORE)) {
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::microseconds(20000));
  }
}

/// The first word of the command line that is not an option: the subcommand.
std::string subcommand(const std::vector<std::string>& args) {
  for (const std::string& a : args)
    if (!a.empty() && a[0] != '-') return a;
  return {};
}

/// The commands that split their work across ranks (the others would repeat it on every rank).
bool splits_across_ranks(const std::string& command) {
  return command == "build" || command == "evaluate" || command == "zonal" || command == "basis" ||
         command == "gi-basis";
}

}  // namespace

bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"})
    if (std::getenv(name)) return true;
  return false;
}

MpiWorld::MpiWorld(int& argc, char**& argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  set_world(this);
}

MpiWorld::~MpiWorld() {
  set_world(nullptr);
  if (!finalized_) MPI_Finalize();
}

int MpiWorld::run_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  int code = 0;
  if (size_ > 1 && !splits_across_ranks(subcommand(args))) {
    if (rank_ == 0)
      print(err, "matlas: error: only `matlas build`, `evaluate`, `zonal` and `basis` split their work across MPI "
                 "ranks; run "
                 "`matlas %s` without mpirun (or with -np 1)\n", subcommand(args).c_str());
    code = 2;
    failure_agreed_ = true;  // every rank comes to the same conclusion
  } else {
    code = run(args, out, err);
  }
  out.flush();
  err.flush();
  if (code != 0 && !failure_agreed_ && size_ > 1) {
    print(err, "matlas: rank %d of %d failed alone: stopping every rank\n", rank_, size_);
    err.flush();
    MPI_Abort(MPI_COMM_WORLD, code);
  }
  MPI_Finalize();
  finalized_ = true;
  return code;
}

void MpiWorld::sum(std::span<double> values) {
  for (std::size_t done = 0; done < values.size(); done += kMaxCount) {
    const auto count = static_cast<int>(std::min(kMaxCount, values.size() - done));
    MPI_Allreduce(MPI_IN_PLACE, values.data() + done, count, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  }
}

namespace {

/// MPI reduction of (value, low) pairs: inout += in with TwoSum, the rounding error kept in low.
void add_compensated_pairs(void* in, void* inout, int* count, MPI_Datatype*) {
  const auto* a = static_cast<const double*>(in);
  auto* b = static_cast<double*>(inout);
  for (int k = 0; k < *count; ++k, a += 2, b += 2) {
    const double sum = a[0] + b[0];
    const double back = sum - b[0];
    b[1] += a[1] + ((b[0] - (sum - back)) + (a[0] - back));
    b[0] = sum;
  }
}

}  // namespace

void MpiWorld::sum_compensated(std::span<double> value, std::span<double> low) {
  MATLAS_CHECK_EQ(value.size(), low.size());
  std::vector<double> pairs(2 * value.size());
  for (std::size_t k = 0; k < value.size(); ++k) pairs[2 * k] = value[k], pairs[2 * k + 1] = low[k];
  MPI_Datatype pair;
  MPI_Type_contiguous(2, MPI_DOUBLE, &pair);
  MPI_Type_commit(&pair);
  MPI_Op op;
  MPI_Op_create(&add_compensated_pairs, 1, &op);
  for (std::size_t done = 0; done < value.size(); done += kMaxCount) {
    const auto count = static_cast<int>(std::min(kMaxCount, value.size() - done));
    MPI_Allreduce(MPI_IN_PLACE, pairs.data() + 2 * done, count, pair, op, MPI_COMM_WORLD);
  }
  MPI_Op_free(&op);
  MPI_Type_free(&pair);
  for (std::size_t k = 0; k < value.size(); ++k) value[k] = pairs[2 * k], low[k] = pairs[2 * k + 1];
}

std::vector<std::uint64_t> MpiWorld::all_gather(std::uint64_t value) {
  std::vector<std::uint64_t> all(static_cast<std::size_t>(size_));
  MPI_Allgather(&value, 1, MPI_UINT64_T, all.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD);
  return all;
}

std::vector<std::byte> MpiWorld::gather(std::span<const std::byte> bytes) {
  MATLAS_CHECK_LE(bytes.size(), std::size_t{INT_MAX});  // one rank's gathered bytes fit an MPI count
  const int mine = static_cast<int>(bytes.size());
  std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_));
  MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::vector<std::byte> all;
  if (rank_ == 0) {
    std::size_t total = 0;
    for (std::size_t r = 0; r < counts.size(); ++r) {
      MATLAS_CHECK_LE(total, std::size_t{INT_MAX});  // the gathered bytes fit an MPI displacement
      offsets[r] = static_cast<int>(total);
      total += static_cast<std::size_t>(counts[r]);
    }
    all.resize(total);
  }
  MPI_Gatherv(bytes.data(), mine, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, 0, MPI_COMM_WORLD);
  return all;
}

void MpiWorld::broadcast(std::string& text) {
  std::uint64_t length = text.size();
  MPI_Bcast(&length, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  MATLAS_CHECK_LE(length, std::uint64_t{INT_MAX});  // a broadcast text fits an MPI count
  text.resize(static_cast<std::size_t>(length));
  MPI_Bcast(text.data(), static_cast<int>(length), MPI_CHAR, 0, MPI_COMM_WORLD);
}

std::string MpiWorld::first_error(const std::string& message) {
  const int mine = message.empty() ? size_ : rank_;
  int lowest = size_;
  MPI_Request request;
  MPI_Iallreduce(&mine, &lowest, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD, &request);
  wait_gently(request);
  if (lowest == size_) return {};
  failure_agreed_ = true;
  std::uint64_t length = rank_ == lowest ? message.size() : 0;
  MPI_Bcast(&length, 1, MPI_UINT64_T, lowest, MPI_COMM_WORLD);
  std::string text = rank_ == lowest ? message : std::string(static_cast<std::size_t>(length), '\0');
  MPI_Bcast(text.data(), static_cast<int>(length), MPI_CHAR, lowest, MPI_COMM_WORLD);
  return "rank " + std::to_string(lowest) + " of " + std::to_string(size_) + ": " + text;
}

}  // namespace matlas::cli
