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
  std::optional<double> target_error;
  bool spp_given = false;
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
  std::vector<render::RefinementState> refined;
  if (a.target_error && a.basis) throw Error("--target-error renders the cells; --basis composes them: give one");
  if (a.target_error && !(*a.target_error > 0 && *a.target_error < 1))
    throw Error("--target-error must be in (0, 1) (a relative RMS error, e.g. 0.01), got " + std::to_string(*a.target_error));
  if (a.basis) {
    const render::ImageBasis basis = render::ImageBasis::open(*a.basis);
    image = atlas::render_gallery(model, entries, nullptr, nullptr, &basis, progress);
  } else {
    const render::Scene scene(a.options.scene_description());
    render::RenderSettings settings = a.options.settings();
    if (a.target_error && !a.spp_given) settings.spp = 4096;  // the most samples per pixel of a cell
    image = atlas::render_gallery(model, entries, &scene, &settings, nullptr, progress, a.target_error.value_or(0.0),
                                  &refined);
  }
  write_image(a.output, image, a.options.tone());
  if (!refined.empty()) {
    const auto [fewest, most] = std::minmax_element(refined.begin(), refined.end(), [](const auto& x, const auto& y) { return x.spp < y.spp; });
    double worst = 0;
    for (const auto& st : refined) worst = std::max(worst, st.relative_error);
    print(io.out, "cells refined: %d-%d spp, estimated error at most %.2f %%%s\n", fewest->spp, most->spp, 100 * worst,
          worst <= *a.target_error ? "" : " (--spp reached before the target)");
  }
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
  cmd->add_option("--target-error", a->target_error,
                  "Refine every cell until its estimated relative RMS error inside the object is at most this (e.g. "
                  "0.01), with adaptive sampling; --spp is then the most samples per pixel (default 4096)");
  cmd->callback([io, a, cmd] {
    a->spp_given = cmd->get_option("--spp")->count() > 0;
    run_gallery(*a, io);
  });
}

}  // namespace

MATLAS_COMMAND(64, add_gallery_command);

}  // namespace matlas::cli
