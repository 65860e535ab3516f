// matlas: the command-line entry point, a thin wrapper over cli::run (cli/run.h). Exit codes:
// 0 success, 1 bad input or failed operation, 2 usage error. Started by an MPI launcher
// (`mpirun -np P matlas build ...`, when built with MPI), it runs as one rank of P
// (cli/mpi_world.h).
#include <iostream>
#include <string>
#include <vector>

#include "cli/run.h"
#include "core/atomic_file.h"
#ifdef MATLAS_WITH_MPI
#include "cli/mpi_world.h"
#endif

int main(int argc, char** argv) {
  // An interrupted command (Ctrl-C, kill) leaves no TARGET.tmp-PID files behind.
  matlas::remove_temporaries_on_signals();
  const std::vector<std::string> args(argv + 1, argv + argc);
#ifdef MATLAS_WITH_MPI
  if (matlas::cli::launched_by_mpi()) {
    matlas::cli::MpiWorld mpi(argc, argv);
    return mpi.run_command(args, std::cout, std::cerr);
  }
#endif
  return matlas::cli::run(args, std::cout, std::cerr);
}
