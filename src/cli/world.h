#pragma once
// The processes a command runs in: one (serial_communicator()) unless `matlas` was started by an
// MPI launcher (`mpirun -np P matlas build ...`), in which case main() sets the MPI world
// (cli/mpi_world.h, built only when CMake finds MPI) for the command's life.
#include "core/communicator.h"

namespace matlas::cli {

/// The world communicator: MPI's when set, else the serial one.
Communicator& world();
/// Sets (or, with null, clears) the world communicator.
void set_world(Communicator* comm);

}  // namespace matlas::cli
