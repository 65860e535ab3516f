// matlas map: the latent map of a model as a picture (albedo, predictive variance, plausibility or
// thumbnails), through the same grid and layers as the server's map (atlas/).
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "atlas/latent_map.h"
#include "cli/commands.h"
#include "cli/print.h"
#include "cli/latent_point.h"
#include "core/error.h"
#include "core/file_io.h"
#include "manifold/model.h"
#include "render/text.h"

namespace matlas::cli {

namespace {

struct MapArgs {
  std::string model, output, layer = "albedo", plane = "dims", dims = "0,1", frame = "all";
  std::optional<std::string> at, basis;
  int size = 768, cells = 160, thumbnails = 10;
  double margin = 0.1, gain = 1.0;
  std::string fade = "0.5,0.9";
  bool no_labels = false, no_legend = false;
};

void run_map(const MapArgs& a, const Io& io) {
  refuse_output_among_inputs(a.output, {a.model, a.basis.value_or("")});
  const Model model = Model::open(a.model);
  atlas::MapOptions o;
  o.size = a.size;
  o.cells = a.cells;
  o.thumbnails = a.thumbnails;
  o.labels = !a.no_labels;
  o.style.albedo_gain = a.gain;
  o.legend = !a.no_legend;
  const Eigen::VectorXd fade = parse_point(a.fade);
  if (fade.size() != 2 || !(fade[0] >= 0) || !(fade[1] > fade[0]))
    throw Error("--fade '" + a.fade + "': expected two variances FROM,TO with 0 <= FROM < TO, e.g. 0.5,0.9");
  o.style.fade_from = fade[0];
  o.style.fade_to = fade[1];
  o.layer = atlas::map_layer_from_name(a.layer, "--layer");
  Eigen::VectorXd at = model.latent().colwise().mean().transpose();
  if (a.at) {
    at = parse_point(*a.at);
    if (at.size() != model.dim()) throw Error("--at has " + std::to_string(at.size()) + " coordinates, the model q = " + std::to_string(model.dim()));
  }
  atlas::LatentPlane plane;
  if (model.dim() == 1) {
    plane = atlas::LatentPlane::automatic(model, a.margin);
  } else if (a.plane == "pca") {
    plane = atlas::LatentPlane::pca(model, at, a.margin);
  } else if (a.plane == "dims") {
    const Eigen::VectorXd d = parse_point(a.dims, "--dims");
    if (d.size() != 2) throw Error("--dims '" + a.dims + "': expected two dimensions, e.g. 0,1");
    for (int k = 0; k < 2; ++k)
      if (d[k] != std::floor(d[k]) || d[k] < 0 || d[k] >= model.dim())
        throw Error("--dims '" + a.dims + "': dimensions are integers in [0, " + std::to_string(model.dim() - 1) + "]");
    plane = atlas::LatentPlane::from_dims(model, static_cast<int>(d[0]), static_cast<int>(d[1]), at, a.margin);
  } else {
    throw Error("--plane '" + a.plane + "': expected dims or pca");
  }
  int outside = 0;
  if (a.frame == "core") outside = atlas::frame_core(model, plane, a.margin);
  else if (a.frame != "all") throw Error("--frame '" + a.frame + "': expected all or core");
  std::optional<render::ImageBasis> basis;
  if (a.basis) {
    basis = render::ImageBasis::open(*a.basis);
    o.basis = &*basis;
  }
  TerminalProgress progress;
  const Image map = atlas::render_latent_map(model, plane, o, progress);
  write_image(a.output, map, ToneMap{});
  std::string labels;
  if (o.labels && !render::text_available()) {
    labels = "; labels skipped: install fonts-dejavu-core";
  } else if (o.labels) {
    const int shown = atlas::map_labels(model, plane, o).shown();
    if (shown < model.count() - outside)
      labels = "; " + std::to_string(model.count() - outside - shown) + " of " + std::to_string(model.count() - outside) +
               " labels hidden where they would overlap (larger --size or --frame core shows more)";
  }
  if (outside > 0) labels += "; " + std::to_string(outside) + " materials outside the core frame";
  print(io.out, "wrote %s (%dx%d, %s layer, interpolation %s, u in [%.3g, %.3g], v in [%.3g, %.3g])%s\n",
              a.output.c_str(), map.width, map.height, a.layer.c_str(),
              to_string(model.interpolation()), plane.u_min, plane.u_max,
              plane.v_min, plane.v_max, labels.c_str());
}

void add_map_command(CLI::App& app, const Io& io) {
  auto* cmd = app.add_subcommand("map", "Draw the latent map of a model (albedo, variance, plausibility or rendered thumbnails)");
  auto a = std::make_shared<MapArgs>();
  cmd->add_option("model", a->model, ".matlas model")->required();
  cmd->add_option("-o,--output", a->output, "Output image (.png or .exr)")->required();
  cmd->add_option("--layer", a->layer, "albedo, variance, plausibility or image (needs --basis)")->capture_default_str();
  cmd->add_option("--basis", a->basis, "Image basis for the image layer (matlas basis)");
  cmd->add_option("--plane", a->plane, "For q > 2: dims (see --dims) or pca")->capture_default_str();
  cmd->add_option("--dims", a->dims, "The two latent dimensions of the plane")->capture_default_str();
  cmd->add_option("--at", a->at, "Point fixing the other coordinates (default: latent mean)");
  cmd->add_option("--size", a->size, "Longer side of the map in pixels (the other follows the data's aspect)")->capture_default_str();
  cmd->add_option("--cells", a->cells, "Grid cells along the longer side (albedo, variance)")->capture_default_str();
  cmd->add_option("--thumbnails", a->thumbnails, "Thumbnails along the longer side (image layer)")->capture_default_str();
  cmd->add_option("--frame", a->frame,
                  "all: the box of every latent point; core: of the materials within 4 median distances of the "
                  "median point (when a few outliers stretch the box)")
      ->capture_default_str();
  cmd->add_option("--margin", a->margin, "Margin around the data, fraction of its extent")
      ->check(finite_number())
      ->capture_default_str();
  cmd->add_option("--gain", a->gain, "Albedo display gain")->check(finite_number())->capture_default_str();
  cmd->add_option("--fade", a->fade,
                  "Predictive variances FROM,TO over which the albedo/image layers (and the plausibility "
                  "layer of convex weights) fade into the hatched 'no data here' grey")
      ->capture_default_str();
  cmd->add_flag("--no-labels", a->no_labels, "Do not write material names");
  cmd->add_flag("--no-legend", a->no_legend, "No legend strip under the map");
  cmd->callback([io, a] { run_map(*a, io); });
}

}  // namespace

MATLAS_COMMAND(63, add_map_command);

}  // namespace matlas::cli
