#include "cli/world.h"

namespace matlas::cli {

namespace {
Communicator* g_world = nullptr;
}

Communicator& world() { return g_world ? *g_world : serial_communicator(); }

void set_world(Communicator* comm) { g_world = comm; }

}  // namespace matlas::cli
