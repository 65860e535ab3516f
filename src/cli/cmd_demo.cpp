// matlas demo [DIR]: the one-command tour. Makes the synthetic demo database (or takes a folder of
// MERL files), builds its model, prepares the previews and serves the material browser. Everything
// is cached (~/.cache/matlas, or --cache): a second run starts in seconds, and the model is rebuilt
// only when the input files (names, sizes, modification times) or the build options change.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "brdf/catalog.h"
#include "cli/commands.h"
#include "cli/print.h"
#include "cli/serve_options.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/progress.h"
#include "formats/synth_database.h"
#include "manifold/build.h"
#include "manifold/material_set.h"
#include "manifold/model.h"
#include "server/atlas_server.h"
#include "server/basis_previews.h"
#include "server/serving.h"

namespace matlas::cli {

namespace {

namespace fs = std::filesystem;

struct DemoArgs {
  std::string dir;
  std::string host = "127.0.0.1";
  int port = 8080;
  bool no_serve = false;
  std::string cache;
  std::string web_root;
  int dim = 2;
  int size = 256;
  int spp = 32;
  std::string grid;  ///< "TH,TD,PD" (tests)
  int count = 0;     ///< > 0: a random catalogue of this many materials (benchmarks)
  std::uint64_t seed = 1;
  bool log = false;
  GiServeArgs gi;
};

MerlDims parse_grid(const std::string& text) {
  if (text.empty()) return {};
  MerlDims d;
  char c1 = 0, c2 = 0;
  std::istringstream in(text);
  if (!(in >> d.theta_h >> c1 >> d.theta_d >> c2 >> d.phi_d) || c1 != ',' || c2 != ',' || d.theta_h < 2 ||
      d.theta_d < 2 || d.phi_d < 2 || d.theta_h > 90 || d.theta_d > 90 || d.phi_d > 180)
    throw Error("--grid '" + text + "': expected THETA_H,THETA_D,PHI_D (at most 90,90,180)");
  return d;
}

/// The demo database in the cache, written once (again only if the catalogue or grid changed).
fs::path demo_database(const fs::path& cache, const MerlDims& dims, int count, std::uint64_t seed,
                       ProgressSink& progress, const Io& io) {
  const auto catalog = count > 0 ? random_catalog(count, seed) : demo_catalog();
  std::string stamp = dims.to_string() + "\n";
  for (const auto& m : catalog) stamp += m.name + "\n";
  const std::string kind = count > 0 ? "random" + std::to_string(count) + "-s" + std::to_string(seed) + "-" : "";
  const fs::path dir = cache / ("demo-db-" + kind + std::to_string(dims.theta_h) + "x" + std::to_string(dims.theta_d) +
                                "x" + std::to_string(dims.phi_d));
  const fs::path stamp_file = dir / "catalog.txt";
  std::error_code ec;
  if (fs::exists(stamp_file, ec) && read_file(stamp_file) == stamp) return dir;
  print(io.err, "writing the demo database (%zu synthetic materials) to %s\n", catalog.size(),
               dir.string().c_str());
  write_database(dir, catalog, progress, dims);
  write_file_atomic(stamp_file, stamp);
  return dir;
}

/// Key of a build: the input files' names, sizes and modification times, and the options.
std::string inputs_key(const MaterialSet& set, int dim) {
  // v2: default builds with the convex interpolation, the cube-root layout and the latent priors;
  // v3: with the default starts (3 for q <= 2; v2 models had 1) and the OpenBLAS arithmetic.
  std::string text = "v3 q=" + std::to_string(dim) + "\n";
  for (std::size_t i = 0; i < set.size(); ++i) {
    const auto& p = set.file(i).path();
    text += set.name(i) + " " + std::to_string(fs::file_size(p)) + " " +
            std::to_string(fs::last_write_time(p).time_since_epoch().count()) + "\n";
  }
  return hex64(xxh3_64(text));
}

void run_demo(const DemoArgs& a, const Io& io) {
  server::block_stop_signals();
  const fs::path cache = a.cache.empty() ? server::default_cache_dir() : fs::path(a.cache);
  TerminalProgress progress;

  const fs::path db = a.dir.empty() ? demo_database(cache, parse_grid(a.grid), a.count, a.seed, progress, io) : fs::path(a.dir);
  const MaterialSet set = MaterialSet::open({db});
  const fs::path model_path = cache / "models" / (fs::weakly_canonical(fs::absolute(db)).filename().string() + "-" + inputs_key(set, a.dim).substr(0, 8) + ".matlas");
  if (!fs::exists(model_path)) {
    print(io.err, "building the model of %zu materials from %s (q = %d)\n", set.size(), db.string().c_str(),
                 a.dim);
    fs::create_directories(model_path.parent_path());
    BuildOptions o;
    o.dim = a.dim;
    build_model(set, o, model_path, progress);
  }
  const Model model = Model::open(model_path);
  print(io.err, "model: %s\n", model_path.string().c_str());

  server::BasisPreviewOptions po;
  po.size = a.size;
  po.spp = a.spp;
  po.cache_dir = cache / "bases";
  auto previews = std::make_shared<server::BasisPreviews>(model, po);
  print(io.err, "preparing previews (%s on %s, %dx%d, %d spp)\n", previews->default_environment().c_str(),
               previews->default_object().c_str(), a.size, a.size, a.spp);
  previews->prepare_default(progress);
  if (a.no_serve) {
    print(io.out, "demo ready: model %s, image basis %s\n", model_path.string().c_str(),
                previews->cache_path(previews->default_environment(), previews->default_object()).string().c_str());
    return;
  }

  server::ServerOptions so = server_options(a.host, a.port, a.web_root, a.log, io);
  so.reload = model_reloader(po, io);
  so.gi_scenes = gi_scenes_factory(a.gi, io);
  server::AtlasServer srv(model, previews, so);
  note_missing_web_ui(srv, io);
  server::serve_until_signal(srv, [&](const std::string& url) {
    print(io.out, "matlas demo: open %s  (%d materials; Ctrl-C stops)\n", url.c_str(), model.count());
    io.out.flush();
  });
}

void add_demo_command(CLI::App& app, const Io& io) {
  auto a = std::make_shared<DemoArgs>();
  auto* cmd = app.add_subcommand(
      "demo", "Build and serve the material browser: the synthetic demo database, or a folder of MERL files");
  cmd->add_option("dir", a->dir, "Folder of MERL .binary files (default: the synthetic demo database)");
  cmd->add_option("--host", a->host, "Address to listen on")->capture_default_str();
  cmd->add_option("--port", a->port, "Port (0: any free port)")->check(CLI::Range(0, 65535))->capture_default_str();
  cmd->add_flag("--no-serve", a->no_serve, "Prepare (database, model, previews) and exit");
  cmd->add_option("--cache", a->cache, "Cache folder (default: $MATLAS_CACHE or ~/.cache/matlas)");
  cmd->add_option("--web-root", a->web_root, "Built web UI folder (default: web/dist near the executable)");
  cmd->add_option("-q,--dim", a->dim, "Latent dimension")->check(CLI::Range(1, 10))->capture_default_str();
  cmd->add_option("--size", a->size, "Preview size in pixels")->check(CLI::Range(32, 1024))->capture_default_str();
  cmd->add_option("--spp", a->spp, "Samples per pixel of the preview bases")->check(CLI::Range(1, 4096))->capture_default_str();
  cmd->add_option("--grid", a->grid, "Grid of the synthetic database, THETA_H,THETA_D,PHI_D (small grids for tests)");
  cmd->add_option("--count", a->count, "A random synthetic catalogue of N materials instead of the demo set (benchmarks)")
      ->check(CLI::Range(2, 10000));
  cmd->add_option("--seed", a->seed, "Seed of the random catalogue")->capture_default_str();
  cmd->add_flag("--log", a->log, "Print one line per request on stderr");
  add_gi_serve_options(*cmd, a->gi);
  cmd->callback([io, a] { run_demo(*a, io); });
}

}  // namespace

MATLAS_COMMAND(5, add_demo_command);

}  // namespace matlas::cli
