// GI basis accuracy (docs/GI.md): for map points between neighbouring materials of a model, the
// GI image composed from a basis (I1 exact, I2 interpolated with the map's weights) against a full
// path-traced render of m(x) with the same random numbers, next to the Monte Carlo noise of the
// render (two seeds). Also the I2 approximations by the mean material and by the nearest input.
//
//   bench_gi_accuracy MODEL SCENE OBJECT WIDTH HEIGHT SPP POINTS [OUT_DIR]
//
// Errors are relative L1: sum |a - b| / sum |b| over pixels and channels; "reflection" restricts
// the sums to pixels off the object (P > 0) where the object's part (N z + I2) is at least 5 % of
// the pixel. OUT_DIR receives PNGs of the first point: reference, composed, 10 x |difference|.
#include <chrono>
#include <cstdio>
#include <string>

#include "atlas/gi_basis.h"
#include "atlas/model_material.h"
#include "formats/image_io.h"
#include "manifold/model.h"

namespace {

using namespace matlas;
using namespace matlas::atlas;
using namespace matlas::pathtrace;

struct Error2 {
  double all = 0, reflection = 0;
};

Error2 relative_l1(const Image& a, const Image& b, const std::vector<bool>& reflection) {
  double d = 0, s = 0, dr = 0, sr = 0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    const double diff = std::abs(static_cast<double>(a.rgb[i]) - b.rgb[i]), v = std::abs(static_cast<double>(b.rgb[i]));
    d += diff, s += v;
    if (reflection[i / 3]) dr += diff, sr += v;
  }
  return {d / s, sr > 0 ? dr / sr : 0.0};
}

Image add(const Image& a, const Image& b, float scale = 1.0f) {
  Image out = a;
  for (std::size_t i = 0; i < out.rgb.size(); ++i) out.rgb[i] += scale * b.rgb[i];
  return out;
}

double seconds(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 8) {
    std::fprintf(stderr, "usage: %s MODEL SCENE OBJECT WIDTH HEIGHT SPP POINTS [OUT_DIR]\n", argv[0]);
    return 2;
  }
  try {
    const Model model = Model::open(argv[1]);
    const World world(load_scene(argv[2], argv[3]));
    TraceSettings settings;
    settings.width = std::stoi(argv[4]);
    settings.height = std::stoi(argv[5]);
    settings.spp = std::stoi(argv[6]);
    const int points = std::stoi(argv[7]);
    const std::string out_dir = argc > 8 ? argv[8] : "";
    auto t = std::chrono::steady_clock::now();
    GiBasisOptions options;
    options.batch = 28;
    const GiBasis basis = build_gi_basis(model, world, settings, options);
    std::printf("scene %s/%s %dx%d %d spp, n = %d: basis traced in %.1f s\n", argv[2], argv[3], settings.width,
                settings.height, settings.spp, model.count(), seconds(t));
    std::printf("%5s %8s %8s %9s %9s %9s %9s %9s %9s\n", "point", "I2share", "err", "err_refl", "noise256",
                "noise_rfl", "err_mean", "err_near", "err_none");
    const int n = model.count();
    const Eigen::MatrixXd& latent = model.latent();
    double sum[8] = {};
    for (int j = 0; j < points; ++j) {
      // Midway between a material and its nearest latent neighbour.
      const int a = (j * 37) % n;
      int b = -1;
      for (int i = 0; i < n; ++i)
        if (i != a && (b < 0 || (latent.row(i) - latent.row(a)).squaredNorm() < (latent.row(b) - latent.row(a)).squaredNorm()))
          b = i;
      const Eigen::VectorXd x = 0.5 * (latent.row(a) + latent.row(b)).transpose();
      const Eigen::VectorXd w = model.weights(x);
      const auto bank = atlas::model_point_bank(model, w);
      const TraceImages ref = trace(world, bank.get(), settings);
      TraceSettings other = settings;
      other.seed = settings.seed + 1000;
      const Image ref2 = trace(world, bank.get(), other).full(0);
      const Image full = ref.full(0);
      std::vector<bool> reflection(full.pixel_count());
      double i2 = 0, total = 0;
      for (std::size_t p = 0; p < reflection.size(); ++p) {
        double obj = 0, pix = 0, pp = 0;
        for (std::size_t c = 0; c < 3; ++c) {
          obj += ref.once[0].rgb[3 * p + c] + ref.more[0].rgb[3 * p + c];
          pix += full.rgb[3 * p + c];
          pp += ref.p.rgb[3 * p + c];
          i2 += ref.more[0].rgb[3 * p + c];
          total += full.rgb[3 * p + c];
        }
        reflection[p] = pp > 0 && obj >= 0.05 * pix;
      }
      const Image composed = basis.compose(w);
      const Error2 err = relative_l1(composed, full, reflection);
      // Noise of one render at this spp: |r1 - r2| / sqrt(2); at 256 spp: times sqrt(spp / 256).
      const Error2 two = relative_l1(ref2, full, reflection);
      const double to256 = std::sqrt(settings.spp / 256.0) / std::sqrt(2.0);
      // Other I2 approximations: the mean material's I2, the nearest input's, none.
      const Image i1 = basis.compose(w, GiBasis::Part::i1);
      const Image i2_mean = add(basis.image(GiBasis::Part::all, 0), basis.image(GiBasis::Part::i1, 0), -1.0f);
      Eigen::Index nearest = 0;
      w.maxCoeff(&nearest);
      const int k = static_cast<int>(nearest) + 1;
      const Image i2_near = add(basis.image(GiBasis::Part::all, k), basis.image(GiBasis::Part::i1, k), -1.0f);
      const double e_mean = relative_l1(add(i1, i2_mean), full, reflection).all;
      const double e_near = relative_l1(add(i1, i2_near), full, reflection).all;
      const double e_none = relative_l1(i1, full, reflection).all;
      const double row[8] = {i2 / total, err.all, err.reflection, two.all * to256, two.reflection * to256, e_mean, e_near, e_none};
      for (int c = 0; c < 8; ++c) sum[c] += row[c];
      std::printf("%5d %8.4f %8.5f %9.5f %9.5f %9.5f %9.5f %9.5f %9.5f   %s|%s\n", j, row[0], row[1], row[2], row[3],
                  row[4], row[5], row[6], row[7], model.names()[static_cast<std::size_t>(a)].c_str(),
                  model.names()[static_cast<std::size_t>(b)].c_str());
      std::fflush(stdout);
      if (j == 0 && !out_dir.empty()) {
        ToneMap tone;
        tone.curve = ToneMap::Curve::aces;
        write_png(out_dir + "/" + argv[2] + "_reference.png", full, tone);
        write_png(out_dir + "/" + argv[2] + "_composed.png", composed, tone);
        Image diff(full.width, full.height);
        for (std::size_t i = 0; i < diff.rgb.size(); ++i) diff.rgb[i] = 10.0f * std::abs(composed.rgb[i] - full.rgb[i]);
        write_png(out_dir + "/" + argv[2] + "_difference_x10.png", diff, tone);
      }
    }
    std::printf("%5s %8.4f %8.5f %9.5f %9.5f %9.5f %9.5f %9.5f %9.5f\n", "mean", sum[0] / points, sum[1] / points,
                sum[2] / points, sum[3] / points, sum[4] / points, sum[5] / points, sum[6] / points, sum[7] / points);
    // Composition time at this size.
    t = std::chrono::steady_clock::now();
    const Eigen::VectorXd w = model.weights(latent.row(0).transpose());
    Image out(basis.width(), basis.height());
    for (int r = 0; r < 20; ++r) basis.compose(w, GiBasis::Part::all, out.rgb.data());
    std::printf("compose %dx%d from n = %d: %.2f ms\n", basis.width(), basis.height(), n, 1e3 * seconds(t) / 20);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
