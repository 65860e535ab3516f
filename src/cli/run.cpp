#include "cli/run.h"

#include <exception>

#include <CLI/CLI.hpp>

#include "cli/commands.h"
#include "core/error.h"

namespace matlas::cli {

int run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  const Io io{out, err};
  CLI::App app{"matlas: a material atlas built from measured BRDFs (Soler et al. 2018)", "matlas"};
  app.set_version_flag("--version", std::string("matlas ") + MATLAS_VERSION);
  app.require_subcommand(1);
  app.fallthrough(false);

  for (const auto& command : registered_commands()) command.add(app, io);

  try {
    std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
    app.parse(reversed);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e, out, err);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e, out, err);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e, out, err);
  } catch (const CLI::ParseError& e) {
    app.exit(e, out, err);
    return 2;
  } catch (const matlas::Error& e) {
    print(err, "matlas: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    print(err, "matlas: internal error: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace matlas::cli
