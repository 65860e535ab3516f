// matlas basis: the basis of a model in a scene, for instant images of any map point (composed
// by `matlas render --basis`, the browser's previews and scene view):
// - the previews' scene (--scene sphere, bunny, suzi or a mesh): an image basis rendered by direct
//   lighting (atlas/model_basis.h), in float16 or float32, optionally with a low-rank form;
// - a GI scene (--scene floor, box, NAME@VIEW or a .json file): a GI basis path-traced in passes
//   of materials, resumable from its cache (atlas/gi_basis.h).
// `gi-basis` is its former name for GI scenes, kept as a deprecated alias with its defaults.
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "atlas/gi_basis.h"
#include "atlas/model_basis.h"
#include "cli/commands.h"
#include "cli/print.h"
#include "cli/render_options.h"
#include "cli/world.h"
#include "core/error.h"
#include "core/file_io.h"
#include "manifold/model.h"
#include "pathtrace/scene_spec.h"
#include "pathtrace/world.h"

namespace matlas::cli {

namespace {

struct BasisArgs {
  std::string model, output, cache;
  std::string precision = "f16";
  std::string rank = "none";
  double tolerance = 1e-3;
  int batch = 16;
  RenderOptions options;
  PathOptions path;
  std::set<std::string> given;
};

/// The previews' scene: an image basis.
void run_image_basis(const BasisArgs& a, const Io& io) {
  refuse_options(a.given, std::array{"--object", "--density", "--max-depth", "--batch", "--cache"},
                 "the previews' scene (a GI scene's basis: --scene floor, box or a .json file)");
  if (a.precision != "f16" && a.precision != "f32") throw Error("--precision must be f16 or f32");
  refuse_output_among_inputs(a.output, a.options.input_files({a.model}));
  // Under mpirun every rank renders its share of the materials; rank 0 gathers them and writes.
  Communicator& comm = world();
  std::optional<Model> model;
  std::optional<render::Scene> scene;
  run_collectively(comm, [&] {
    model.emplace(Model::open(a.model));
    scene.emplace(a.options.scene_description());
  });
  TerminalProgress progress(comm.is_root());
  render::ImageBasis basis = atlas::render_basis(*model, *scene, a.options.settings(), progress, comm);
  // Rank 0 alone finishes; the others wait for its outcome (a failure ends every rank with it).
  run_collectively(comm, [&] {
    if (!comm.is_root()) return;
    print(io.out, "rendered %d material images (%dx%d, %d spp); object covers %.1f%% of the pixels\n", basis.count(),
          basis.width(), basis.height(), a.options.spp, 100.0 * basis.active_fraction());
    if (a.rank != "none") {
      int max_rank = 0;
      double tolerance = a.tolerance;
      if (a.rank == "full") tolerance = 0.0;
      else if (a.rank != "auto") {
        try {
          max_rank = std::stoi(a.rank);
        } catch (const std::exception&) {
          throw Error("--rank '" + a.rank + "': expected none, auto, full or a number");
        }
        if (max_rank <= 0) throw Error("--rank must be positive");
        tolerance = 0.0;
      }
      const render::LowRankReport r = basis.compress(tolerance, max_rank);
      print(io.out, "low-rank form: rank %d of %d, relative error %.3g (centred), %.3g (images), max abs %.3g\n", r.rank,
            basis.count(), r.relative_error, r.image_relative_error, r.max_abs_error);
    }
    if (a.precision == "f16") {
      render::ImageBasis copy = basis;
      print(io.out, "float16 storage: relative error %.3g\n", copy.convert_to_half());
    }
    basis.save(a.output, a.precision == "f16" ? render::BasisPrecision::f16 : render::BasisPrecision::f32);
    print(io.out, "wrote %s\n", a.output.c_str());
  });
}

/// A GI scene: a GI basis, traced in passes of --batch materials, each cached (a rerun resumes).
void run_gi_basis(const BasisArgs& a, const Io& io) {
  refuse_options(a.given, kPreviewSceneOptions,
                 "a GI scene (--scene " + a.options.scene + ": it says its own lights, camera and environment)");
  refuse_options(a.given, std::array{"--precision", "--rank", "--tolerance"}, "a GI basis (float32, no low-rank form)");
  // Under mpirun every rank traces its share of the materials (each caching its own); rank 0
  // gathers them and writes.
  Communicator& comm = world();
  std::optional<Model> model;
  std::optional<pathtrace::World> scene;
  run_collectively(comm, [&] {
    model.emplace(Model::open(a.model));
    scene.emplace(pathtrace::load_scene(a.options.scene, a.path.object));
    std::vector<std::filesystem::path> inputs{a.model, a.options.scene, a.path.object, scene->spec().environment.map};
    for (const auto& object : scene->spec().objects) inputs.emplace_back(object.mesh);
    refuse_output_among_inputs(a.output, inputs);
  });
  atlas::GiBasisOptions options;
  options.batch = a.batch;
  options.cache = a.cache.empty() ? std::filesystem::path(a.output + ".cache") : std::filesystem::path(a.cache);
  TerminalProgress progress(comm.is_root());
  const auto start = std::chrono::steady_clock::now();
  const atlas::GiBasis basis =
      atlas::build_gi_basis(*model, *scene, a.path.settings(a.options, &*model), options, progress, comm);
  run_collectively(comm, [&] {
    if (comm.is_root()) basis.save(a.output);
  });
  if (!comm.is_root()) return;
  print(io.out, "basis of %d material images + P (%dx%d, %d spp) in %.1f s; cache %s\nwrote %s\n", basis.count() + 1,
        basis.width(), basis.height(), a.options.spp,
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), options.cache.c_str(),
        a.output.c_str());
}

void run_basis(const BasisArgs& a, const Io& io) {
  if (pathtrace::is_scene(a.options.scene)) run_gi_basis(a, io);
  else run_image_basis(a, io);
}

void add_variant(CLI::App& app, const Io& io, const char* name, const char* description, const std::string& scene,
                 int size) {
  auto* cmd = app.add_subcommand(name, description);
  auto a = std::make_shared<BasisArgs>();
  a->options.scene = scene;
  a->options.width = a->options.height = size;
  cmd->add_option("model", a->model, ".matlas model")->required();
  cmd->add_option("-o,--output", a->output, "Output basis (.safetensors)")->required();
  add_render_options(*cmd, a->options);
  cmd->get_option("--scene")
      ->description("The previews' scene, its object: sphere, bunny, suzi or a .glb/.gltf/.obj file (an image basis); "
                    "or a GI scene: floor, box, NAME@VIEW (side, above) or a .json file (a GI basis, path-traced)");
  cmd->add_option("--precision", a->precision, "Image basis: storage f16 or f32")->capture_default_str();
  cmd->add_option("--rank", a->rank, "Image basis: low-rank form none, auto (--tolerance), full, or a rank")
      ->capture_default_str();
  cmd->add_option("--tolerance", a->tolerance, "Image basis: relative error of the automatic rank")->capture_default_str();
  add_path_options(*cmd, a->path);
  cmd->add_option("--batch", a->batch, "GI basis: materials traced per pass")
      ->capture_default_str()
      ->check(CLI::Range(1, 1 << 20));
  cmd->add_option("--cache", a->cache, "GI basis: folder of per-material images (default OUTPUT.cache): a rerun resumes");
  cmd->callback([io, a, cmd, former = std::string(name) != "basis", command = std::string(name)] {
    a->given = given_options(*cmd);
    if (former) io.err << "matlas " << command << " is deprecated: use matlas basis --scene floor (a GI scene)\n";
    run_basis(*a, io);
  });
  if (std::string(name) != "basis") cmd->group("");  // a former name: not listed
}

void add_basis_commands(CLI::App& app, const Io& io) {
  add_variant(app, io, "basis",
              "Render the basis of a model in a scene for instant images of any point: an image basis (the previews' "
              "scene) or a GI basis (floor, box, a .json scene: path-traced, resumable)",
              "sphere", 512);
  add_variant(app, io, "gi-basis", "", "floor", 256);
}

}  // namespace

MATLAS_COMMAND(61, add_basis_commands);

}  // namespace matlas::cli
