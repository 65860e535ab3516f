#include "eval/model_checks.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <random>

#include "brdf/albedo.h"
#include "core/check.h"
#include "core/combination.h"
#include "core/error.h"
#include "core/parallel.h"
#include "manifold/column_blocks.h"
#include "manifold/export.h"
#include "manifold/model_metadata.h"

namespace matlas::eval {

namespace {

/// A direction drawn uniformly from the upper hemisphere, kept off the horizon.
Vec3 random_direction(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double z = 0.02 + 0.98 * u(rng), phi = 2.0 * kPi * u(rng), r = std::sqrt(1.0 - z * z);
  return {r * std::cos(phi), r * std::sin(phi), z};
}

/// Sample latent points: midpoints of the data's consecutive material pairs and random points in
/// the latent bounding box (deterministic).
std::vector<Eigen::VectorXd> sample_points(const Model& model, int count, unsigned seed) {
  std::vector<Eigen::VectorXd> pts;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Eigen::VectorXd lo = model.latent_min(), hi = model.latent_max();
  const int n = model.count();
  MATLAS_CHECK_GT(n, 0);  // a model has materials (the reader refuses an empty one)
  for (int k = 0; k < count; ++k) {
    if (k % 2 == 0) {
      const int a = k % n, b = (k + 1 + k / 2) % n;
      pts.push_back(0.5 * (model.latent().row(a) + model.latent().row(b)).transpose());
    } else {
      Eigen::VectorXd x(lo.size());
      for (Eigen::Index d = 0; d < x.size(); ++d) x(d) = lo(d) + (hi(d) - lo(d)) * u(rng);
      pts.push_back(x);
    }
  }
  return pts;
}

/// Directional albedo of m(x) for weights w with the same rule as directional_albedo(BrdfTable)
/// and the model's stored curves (brdf/albedo.h), but reading the model's signed values (a table
/// would take negative values for "missing"); dropped columns read as 0.
Rgb signed_albedo(const Model& model, const Eigen::VectorXd& w, double theta_o, const AlbedoQuadrature& q) {
  const std::size_t bins = model.dims().bins();
  MATLAS_CHECK_EQ(w.size(), Eigen::Index{model.count()});
  Rgb sum = Rgb::Zero();
  for (const AlbedoTerm& t : albedo_rule(model.dims(), theta_o, q))
    for (int c = 0; c < 3; ++c) {
      const std::size_t v = static_cast<std::size_t>(c) * bins + t.bin;
      if (model.kept(v)) sum[c] += t.weight * model.value(v, w);
    }
  return sum;
}

double relative(double a, double ref) { return std::abs(a - ref) / std::max(std::abs(ref), 1e-6); }

}  // namespace

std::vector<std::size_t> count_negative_values(const Model& model, const Eigen::MatrixXd& weights) {
  const int n = model.count();
  if (weights.rows() != n) throw Error("count_negative_values: weights must have one row per material");
  const Eigen::Index m = weights.cols();
  const std::size_t values = 3 * model.dims().bins();
  const Eigen::MatrixXd wt = weights.transpose();  // m x n
  Eigen::VectorXd weight_of_mean(m);
  for (Eigen::Index j = 0; j < m; ++j) weight_of_mean[j] = Combination::mean_weight(weights.col(j));
  const bool f32 = model.kept_columns() > 0 && model.data_f32(0) != nullptr;
  std::vector<std::size_t> total(static_cast<std::size_t>(m), 0);
  std::mutex mutex;
  constexpr std::size_t kChunk = 8192;
  constexpr Eigen::Index kPointBlock = 128;
  const std::size_t chunks = (values + kChunk - 1) / kChunk;
  parallel_for(0, chunks, [&](std::size_t lo, std::size_t hi) {
    std::vector<std::size_t> local(static_cast<std::size_t>(m), 0);
    Eigen::MatrixXd z(n, static_cast<Eigen::Index>(kChunk));
    Eigen::RowVectorXd mean(static_cast<Eigen::Index>(kChunk));
    Eigen::MatrixXd y(std::min<Eigen::Index>(kPointBlock, m), static_cast<Eigen::Index>(kChunk));
    for (std::size_t chunk = lo; chunk < hi; ++chunk) {
      const std::size_t v0 = chunk * kChunk, v1 = std::min(values, v0 + kChunk);
      Eigen::Index cols = 0;
      for (std::size_t v = v0; v < v1; ++v) {
        const int c = model.column_of(v);
        if (c < 0) continue;
        if (f32) {
          const float* p = model.data_f32(static_cast<std::size_t>(c));
          mean(cols) = model.mean(static_cast<std::size_t>(c));
          for (int i = 0; i < n; ++i) z(i, cols) = static_cast<double>(p[i]);
        } else {
          for (int i = 0; i < n; ++i) z(i, cols) = model.value(v, Eigen::VectorXd::Unit(n, i));
          mean(cols) = model.value(v, Eigen::VectorXd::Zero(n));
        }
        ++cols;
      }
      if (cols == 0) continue;
      // As Model::table: (1 - sum w) mean + sum_i w_i z_i, the mean's weight exactly 0 for weights
      // summing to 1 (Combination), so an exact zero of the inputs is not counted as negative.
      // In blocks of points, so that the values of a block (128 x kChunk, 8 MB) stay in cache:
      // all m points at once made a fresh m x kChunk matrix per chunk (67 MB for a 32 x 32 map),
      // and writing it was most of the time.
      for (Eigen::Index r0 = 0; r0 < m; r0 += kPointBlock) {
        const Eigen::Index rows = std::min<Eigen::Index>(kPointBlock, m - r0);
        y.topLeftCorner(rows, cols).noalias() = wt.middleRows(r0, rows) * z.leftCols(cols);
        y.topLeftCorner(rows, cols).noalias() += weight_of_mean.segment(r0, rows) * mean.head(cols);
        for (Eigen::Index r = 0; r < rows; ++r)
          local[static_cast<std::size_t>(r0 + r)] +=
              static_cast<std::size_t>((y.row(r).head(cols).array() < 0.0).count());
      }
    }
    std::lock_guard lock(mutex);
    for (std::size_t r = 0; r < local.size(); ++r) total[r] += local[r];
  });
  return total;
}

namespace {

InterpolationCheck check_interpolation(const Model& model, const MaterialSet& set, ProgressSink& progress) {
  InterpolationCheck r;
  const int n = model.count();
  if (static_cast<int>(set.size()) != n || !(set.dims() == model.dims())) {
    r.note = "the source folder does not match the model (count or grid)";
    return r;
  }
  Eigen::MatrixXd W(n, n);  // column i: w(x_i)
  for (int i = 0; i < n; ++i) {
    W.col(i) = model.weights(model.latent().row(i).transpose());
    r.max_weight_error = std::max(r.max_weight_error, (W.col(i) - Eigen::VectorXd::Unit(n, i)).cwiseAbs().maxCoeff());
  }
  const Eigen::MatrixXd Wt = W.transpose();
  Eigen::VectorXd weight_of_mean(n);
  for (int i = 0; i < n; ++i) weight_of_mean[i] = Combination::mean_weight(W.col(i));
  std::vector<double> max_abs(static_cast<std::size_t>(n), 0.0), sum_abs(static_cast<std::size_t>(n), 0.0),
      max_val(static_cast<std::size_t>(n), 0.0);
  std::size_t counted = 0;
  BlockOptions options;
  options.label = "checking exact interpolation";
  for_each_column_block(
      set,
      [&](const ColumnBlock& block) {
        Eigen::VectorXd centred(n), rec(n);
        for (std::size_t j = 0; j < block.count; ++j) {
          const std::size_t v = block.first + j;
          const int c = model.column_of(v);
          if ((c >= 0) != static_cast<bool>(block.kept[j])) ++r.column_mismatches;
          if (c < 0 || !block.kept[j]) continue;
          const auto col = static_cast<std::size_t>(c);
          if (const float* p = model.data_f32(col)) {
            // m = (1 - sum w) mean + sum_i w_i z_i, as Model::value computes it.
            for (int i = 0; i < n; ++i) centred(i) = p[i];
            rec = Wt * centred + weight_of_mean * static_cast<double>(model.mean(col));
          } else {
            for (int i = 0; i < n; ++i) rec(i) = model.value(v, W.col(i));
          }
          for (int i = 0; i < n; ++i) {
            const double z = block.values(i, static_cast<Eigen::Index>(j));
            const double e = std::abs(rec(i) - z);
            const auto k = static_cast<std::size_t>(i);
            max_abs[k] = std::max(max_abs[k], e);
            sum_abs[k] += e;
            max_val[k] = std::max(max_val[k], std::abs(z));
          }
          ++counted;
        }
      },
      options, progress);
  r.available = true;
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    r.max_abs_error.push_back(max_abs[k]);
    r.mean_abs_error.push_back(counted ? sum_abs[k] / static_cast<double>(counted) : 0.0);
    r.max_relative_error.push_back(max_val[k] > 0 ? max_abs[k] / max_val[k] : 0.0);
  }
  return r;
}

/// 2. Reciprocity on tables exported at `points`: f(wi, wo) against f(wo, wi) at random pairs.
ReciprocityCheck check_reciprocity(const Model& model, const std::vector<Eigen::VectorXd>& points,
                                   const ModelCheckOptions& options, ProgressSink& progress) {
  ReciprocityCheck check;
  ProgressTask task(progress, "checking reciprocity", points.size());
  std::mt19937_64 rng(options.seed * 7919u + 17u);
  for (const Eigen::VectorXd& x : points) {
    const BrdfTable t = export_table(model, model.weights(x));
    for (int p = 0; p < options.reciprocity_pairs; ++p) {
      const Vec3 wi = random_direction(rng), wo = random_direction(rng);
      const Rgb a = t.lookup(wi, wo), b = t.lookup(wo, wi);
      const double diff = (a - b).abs().maxCoeff();
      if (diff != 0.0) ++check.unequal;
      const double scale = std::max({a.abs().maxCoeff(), b.abs().maxCoeff(), 1e-12});
      check.max_relative_difference = std::max(check.max_relative_difference, diff / scale);
    }
    ++check.points;
    check.pairs += options.reciprocity_pairs;
    task.advance();
  }
  return check;
}

/// 3. Albedo linearity at `points`: the albedo of m(x) against the same combination of the
/// inputs' albedos (signed, clamped on export, and the model's fast curve).
AlbedoCheck check_albedo(const Model& model, const std::vector<Eigen::VectorXd>& points,
                         const ModelCheckOptions& options, ProgressSink& progress) {
  const int n = model.count();
  AlbedoCheck check;
  const std::vector<int> angle_index = {0, 30, 60, 80};
  for (int a : angle_index) check.angles_degrees.push_back(a + 0.5);
  ProgressTask task(progress, "checking albedo linearity", static_cast<std::uint64_t>(n) + points.size());
  std::vector<std::vector<Rgb>> input_albedo(static_cast<std::size_t>(n));  // [material][angle]
  for (int i = 0; i < n; ++i)
    for (double deg : check.angles_degrees)
      input_albedo[static_cast<std::size_t>(i)].push_back(
          signed_albedo(model, model.material_weights(i), deg * kPi / 180.0, options.albedo_quadrature));
  task.advance(static_cast<std::uint64_t>(n));
  for (std::size_t p = 0; p < points.size(); ++p) {
    const Eigen::VectorXd w = model.weights(points[p]);
    const Eigen::VectorXd c = Combination(w).affine();
    const BrdfTable clamped = export_table(model, w);
    const std::vector<Rgb> curve = model.albedo_curve(w);
    for (std::size_t k = 0; k < angle_index.size(); ++k) {
      const double theta = check.angles_degrees[k] * kPi / 180.0;
      Rgb expected = Rgb::Zero();
      for (int i = 0; i < n; ++i) expected += c(i) * input_albedo[static_cast<std::size_t>(i)][k];
      const Rgb got = signed_albedo(model, w, theta, options.albedo_quadrature);
      const Rgb got_clamped = directional_albedo(clamped, theta, options.albedo_quadrature);
      const Rgb fast = curve[static_cast<std::size_t>(angle_index[k])];
      for (int ch = 0; ch < 3; ++ch) {
        check.max_relative_error = std::max(check.max_relative_error, relative(got[ch], expected[ch]));
        check.max_relative_error_clamped =
            std::max(check.max_relative_error_clamped, relative(got_clamped[ch], expected[ch]));
        check.max_relative_error_model = std::max(check.max_relative_error_model, relative(fast[ch], expected[ch]));
        check.rows.push_back({static_cast<double>(p), check.angles_degrees[k], static_cast<double>(ch),
                                   got[ch], expected[ch], got_clamped[ch]});
      }
    }
    task.advance();
  }
  return check;
}

/// 4. Plausibility map: negative values, largest albedo and variance over a grid of the latent
/// plane through the centre of the inputs (axes 0 and 1), 10 % beyond their extent.
PlausibilityMap plausibility_map(const Model& model, const ModelCheckOptions& options, ProgressSink& progress) {
  const int n = model.count();
  PlausibilityMap map;
  const int res = std::max(2, options.map_resolution);
  const Eigen::VectorXd lo = model.latent_min(), hi = model.latent_max();
  const Eigen::VectorXd centre = model.latent().colwise().mean().transpose();
  map.resolution = res;
  map.axis_x = 0;
  map.axis_y = model.dim() > 1 ? 1 : 0;
  auto range = [&](int axis, double& a, double& b) {
    const double margin = 0.1 * std::max(hi(axis) - lo(axis), 1e-9);
    a = lo(axis) - margin, b = hi(axis) + margin;
  };
  range(map.axis_x, map.x_min, map.x_max);
  range(map.axis_y, map.y_min, map.y_max);
  const int rows = model.dim() > 1 ? res : 1;
  Eigen::MatrixXd W(n, res * rows);
  std::vector<Eigen::VectorXd> xs;
  for (int yi = 0; yi < rows; ++yi)
    for (int xi = 0; xi < res; ++xi) {
      Eigen::VectorXd x = centre;
      x(map.axis_x) = map.x_min + (xi + 0.5) / res * (map.x_max - map.x_min);
      if (model.dim() > 1) x(map.axis_y) = map.y_min + (yi + 0.5) / rows * (map.y_max - map.y_min);
      W.col(static_cast<Eigen::Index>(xs.size())) = model.weights(x);
      xs.push_back(x);
    }
  progress.message("plausibility map: " + std::to_string(xs.size()) + " grid points");
  const std::vector<std::size_t> negatives = count_negative_values(model, W);
  map.values = model.kept_columns();
  std::size_t worst = 0;
  for (std::size_t k = 0; k < xs.size(); ++k) {
    const double frac = map.values ? static_cast<double>(negatives[k]) / static_cast<double>(map.values) : 0.0;
    map.negative_fraction.push_back(frac);
    double most = 0;
    for (const Rgb& a : model.albedo_curve(W.col(static_cast<Eigen::Index>(k)))) most = std::max(most, a.maxCoeff());
    map.max_albedo.push_back(most);
    map.variance.push_back(model.variance(xs[k]));
    if (frac > map.worst_negative_fraction) map.worst_negative_fraction = frac, worst = k;
    map.worst_max_albedo = std::max(map.worst_max_albedo, most);
  }
  map.data_max_albedo = model.material_albedo().maxCoeff();
  ExportStats stats;
  (void)export_table(model, W.col(static_cast<Eigen::Index>(worst)), &stats);
  map.export_clamped_at_worst = stats.clamped;
  return map;
}

}  // namespace

ModelChecks run_model_checks(const Model& model, const MaterialSet* sources, const ModelCheckOptions& options,
                             ProgressSink& progress) {
  ModelChecks out;
  out.model_path = model.path().string();
  out.count = model.count();
  out.dim = model.dim();
  out.layout = model.metadata().value("layout_transform", std::string("?"));
  out.latent = model.latent();

  // 1. Exact interpolation.
  if (sources) out.interpolation = check_interpolation(model, *sources, progress);
  else out.interpolation.note = "source tables not available (pass the input folder or keep the files listed in the model)";

  const std::vector<Eigen::VectorXd> points = sample_points(model, options.sample_points, options.seed);

  out.reciprocity = check_reciprocity(model, points, options, progress);
  out.albedo = check_albedo(model, points, options, progress);
  out.map = plausibility_map(model, options, progress);
  return out;
}

}  // namespace matlas::eval
