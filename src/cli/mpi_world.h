#pragma once
// The `matlas` command under an MPI launcher (Open MPI's mpirun, Slurm's srun): MPI's world as
// the command's Communicator (core/communicator.h). Built only when CMake finds MPI
// (MATLAS_WITH_MPI); the rest of matlas never includes mpi.h. One binary serves both: started
// without a launcher, `matlas` never initialises MPI.
//
// Only `build`, `evaluate`, `zonal` and `basis` split their work across ranks; any other command
// refuses to run on more than one rank (every rank would repeat the whole command and write the
// same output). Errors: a failure on one rank is agreed by all in the collective steps
// (run_collectively), every rank exits 1 with the message; a rank that fails outside them (a
// bug, or before the ranks meet) ends every rank with MPI_Abort, so that none waits forever for
// it.
#include <cstdlib>
#include <ostream>
#include <string>
#include <vector>

#include "core/communicator.h"

namespace matlas::cli {

/// True when the process was started by an MPI launcher (its environment names a world size).
bool launched_by_mpi();

class MpiWorld final : public Communicator {
public:
  /// MPI_Init_thread (funneled: only the main thread calls MPI) and set_world(this).
  MpiWorld(int& argc, char**& argv);
  ~MpiWorld() override;
  MpiWorld(const MpiWorld&) = delete;
  MpiWorld& operator=(const MpiWorld&) = delete;

  /// Runs the command (cli::run) on this rank, then MPI_Finalize, or MPI_Abort when the command
  /// failed on this rank without the others knowing. Returns the exit code.
  int run_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

  int rank() const override { return rank_; }
  int size() const override { return size_; }
  void sum(std::span<double> values) override;
  void sum_compensated(std::span<double> value, std::span<double> low) override;
  std::vector<std::uint64_t> all_gather(std::uint64_t value) override;
  std::vector<std::byte> gather(std::span<const std::byte> bytes) override;
  void broadcast(std::string& text) override;
  std::string first_error(const std::string& message) override;

private:
  int rank_ = 0, size_ = 1;
  bool failure_agreed_ = false;  ///< a first_error() found a failure: every rank knows
  bool finalized_ = false;
};

}  // namespace matlas::cli
