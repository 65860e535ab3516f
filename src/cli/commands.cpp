#include "cli/commands.h"

#include <algorithm>

namespace matlas::cli {

namespace {
std::vector<RegisteredCommand>& registry() {
  static std::vector<RegisteredCommand> commands;
  return commands;
}
}  // namespace

bool register_command(int order, CommandFactory add) {
  registry().push_back({order, add});
  return true;
}

std::vector<RegisteredCommand> registered_commands() {
  auto commands = registry();
  std::stable_sort(commands.begin(), commands.end(),
                   [](const auto& a, const auto& b) { return a.order < b.order; });
  return commands;
}

}  // namespace matlas::cli
