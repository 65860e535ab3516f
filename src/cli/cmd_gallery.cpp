// matlas gallery: the plausibility figure (generated and real materials, shuffled, with a key).
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "atlas/gallery.h"
#include "cli/commands.h"
#include "cli/print.h"
#include "cli/render_options.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/file_io.h"
#include "manifold/model.h"
#include "render/image_basis.h"

namespace matlas::cli {

namespace {

struct GalleryArgs {
  std::string model, output;
  std::optional<std::string> key, basis;
  atlas::GalleryOptions gallery;
  RenderOptions options;
};

void run_gallery(GalleryArgs a, const Io& io) {
  const std::filesystem::path key =
      a.key ? std::filesystem::path(*a.key) : std::filesystem::path(a.output).replace_extension(".json");
  std::vector<std::filesystem::path> inputs = a.options.input_files({a.model, a.basis.value_or("")});
  refuse_output_among_inputs(a.output, inputs);
  refuse_output_among_inputs(key, inputs);
  std::error_code ec1, ec2;  // the key must not replace the picture either (neither exists yet, maybe)
  if (std::filesystem::weakly_canonical(key, ec1) == std::filesystem::weakly_canonical(a.output, ec2) && !ec1 && !ec2)
    throw Error("--key " + key.string() + " is the output picture: give the answer key another name");
  const Model model = Model::open(a.model);
  atlas::GalleryStats stats;
  const std::vector<atlas::GalleryEntry> entries = atlas::pick_gallery(model, a.gallery, &stats);
  TerminalProgress progress;
  Image image;
  if (a.basis) {
    const render::ImageBasis basis = render::ImageBasis::open(*a.basis);
    image = atlas::render_gallery(model, entries, nullptr, nullptr, &basis, progress);
  } else {
    const render::Scene scene(a.options.scene_description());
    const render::RenderSettings settings = a.options.settings();
    image = atlas::render_gallery(model, entries, &scene, &settings, nullptr, progress);
  }
  write_image(a.output, image, a.options.tone());
  write_file_atomic(key, atlas::gallery_key(model, entries, stats).dump(2) + "\n");
  print(io.out, "wrote %s and its answer key %s (%d generated, %d real; interpolation %s)\n", a.output.c_str(),
              key.string().c_str(), a.gallery.random, a.gallery.real,
              to_string(model.interpolation()));
  print(io.out, "generated picks: farthest apart in appearance among %d candidates between latent neighbours "
              "(%d above the variance limit, %d implausible, %d copies of a database material); "
              "smallest feature distance between two picks %.2f\n",
              stats.candidates, stats.rejected_variance, stats.rejected_implausible, stats.rejected_copies,
              stats.min_distance);
  if (a.gallery.random + a.gallery.real > 1 && stats.min_distance < 0.3)
    print(io.err, "warning: two picks are only %.2f apart in appearance: the plausible region near the data is "
                 "not varied enough for %d picks (fewer --random, --allow-implausible, or a model with convex "
                 "interpolation)\n",
                 stats.min_distance, a.gallery.random + a.gallery.real);
  for (const std::string& f : stats.relaxed)
    print(io.err, "warning: too few candidates passed the %s filter; it was dropped\n", f.c_str());
}

void add_gallery_command(CLI::App& app, const Io& io) {
  auto* cmd = app.add_subcommand("gallery", "Plausibility gallery: generated and real materials, shuffled, with a key");
  auto a = std::make_shared<GalleryArgs>();
  a->options.width = a->options.height = 256;
  a->options.spp = 32;
  cmd->add_option("model", a->model, ".matlas model")->required();
  cmd->add_option("-o,--output", a->output, "Output image (.png or .exr)")->required();
  add_render_options(*cmd, a->options);
  cmd->remove_option(cmd->get_option("--seed"));  // --seed picks the materials here
  cmd->add_option("--key", a->key, "Answer key JSON (default: output with .json)");
  cmd->add_option("--random", a->gallery.random, "Generated materials")->capture_default_str();
  cmd->add_option("--real", a->gallery.real, "Database materials")->capture_default_str();
  cmd->add_option("--seed", a->gallery.seed, "Seed of the picks and the shuffle")->capture_default_str();
  cmd->add_option("--max-variance", a->gallery.max_variance, "Largest predictive variance of generated points")
      ->capture_default_str();
  cmd->add_option("--min-novelty", a->gallery.min_novelty,
                  "Smallest appearance distance of a generated pick to every database material")
      ->capture_default_str();
  cmd->add_flag("!--allow-implausible", a->gallery.plausible_only,
                "Also pick generated points with negative values or an albedo above the inputs'");
  cmd->add_option("--basis", a->basis, "Compose the cells from an image basis instead of rendering them");
  cmd->callback([io, a] { run_gallery(*a, io); });
}

}  // namespace

MATLAS_COMMAND(64, add_gallery_command);

}  // namespace matlas::cli
