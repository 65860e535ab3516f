#include "eval/model_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <random>

#include "brdf/albedo.h"
#include "core/blas.h"
#include "core/check.h"
#include "core/combination.h"
#include "core/error.h"
#include "core/parallel.h"
#include "eval/statistics.h"
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

/// signed_albedo of every input at once (n x 3): the same rule, reading each term's stored
/// values once (z_i exactly, as model.value(v, e_i)) instead of a length-n sum per input and term.
Eigen::MatrixXd inputs_signed_albedo(const Model& model, double theta_o, const AlbedoQuadrature& q) {
  const std::size_t bins = model.dims().bins();
  const int n = model.count();
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(n, 3);
  std::vector<float> z(static_cast<std::size_t>(n));
  for (const AlbedoTerm& t : albedo_rule(model.dims(), theta_o, q))
    for (int c = 0; c < 3; ++c) {
      const int column = model.column_of(static_cast<std::size_t>(c) * bins + t.bin);
      if (column < 0) continue;
      model.data(static_cast<std::size_t>(column), z.data());
      for (int i = 0; i < n; ++i) sum(i, c) += t.weight * static_cast<double>(z[static_cast<std::size_t>(i)]);
    }
  return sum;
}

double relative(double a, double ref) { return std::abs(a - ref) / std::max(std::abs(ref), 1e-6); }

}  // namespace

std::vector<std::size_t> count_negative_inputs(const Model& model) {
  const int n = model.count();
  const std::size_t columns = model.kept_columns();
  std::vector<std::size_t> total(static_cast<std::size_t>(n), 0);
  std::mutex mutex;
  parallel_for(0, columns, [&](std::size_t lo, std::size_t hi) {
    std::vector<std::size_t> local(static_cast<std::size_t>(n), 0);
    std::vector<float> z(static_cast<std::size_t>(n));
    for (std::size_t c = lo; c < hi; ++c) {
      model.data(c, z.data());
      for (std::size_t i = 0; i < z.size(); ++i) local[i] += z[i] < 0.0f ? 1 : 0;
    }
    std::lock_guard lock(mutex);
    for (std::size_t i = 0; i < local.size(); ++i) total[i] += local[i];
  }, 4096);
  return total;
}

bool non_negative_by_construction(const Eigen::Ref<const Eigen::VectorXd>& w,
                                  const std::vector<std::size_t>& input_negatives) {
  MATLAS_CHECK_EQ(static_cast<std::size_t>(w.size()), input_negatives.size());
  double sum = 0;
  for (Eigen::Index i = 0; i < w.size(); ++i) {
    if (w[i] < 0.0 || (w[i] > 0.0 && input_negatives[static_cast<std::size_t>(i)] > 0)) return false;
    sum += w[i];
  }
  return std::abs(sum - 1.0) <= 1e-9;
}

NegativeCounts count_possible_negatives(const Model& model, const Eigen::MatrixXd& weights,
                                        const std::vector<std::size_t>& input_negatives, double budget) {
  NegativeCounts out;
  out.negatives.assign(static_cast<std::size_t>(weights.cols()), 0);
  out.visited = model.kept_columns();
  std::vector<Eigen::Index> counted;
  for (Eigen::Index j = 0; j < weights.cols(); ++j)
    if (!non_negative_by_construction(weights.col(j), input_negatives)) counted.push_back(j);
  if (counted.empty()) return out;
  const double work = static_cast<double>(counted.size()) * model.count() * 3.0 * static_cast<double>(model.dims().bins());
  out.stride = static_cast<std::size_t>(std::max(1.0, std::ceil(work / budget)));
  const std::vector<std::size_t> found = count_negative_values(model, weights(Eigen::all, counted), out.stride, &out.visited);
  for (std::size_t k = 0; k < counted.size(); ++k) out.negatives[static_cast<std::size_t>(counted[k])] = found[k];
  return out;
}

std::vector<std::size_t> count_negative_values(const Model& model, const Eigen::MatrixXd& weights, std::size_t stride,
                                               std::size_t* visited) {
  const int n = model.count();
  if (weights.rows() != n) throw Error("count_negative_values: weights must have one row per material");
  MATLAS_CHECK_GE(stride, std::size_t{1});
  const Eigen::Index m = weights.cols();
  // Value u of the pass is value u * stride of the table.
  const std::size_t values = (3 * model.dims().bins() + stride - 1) / stride;
  if (visited) {
    *visited = 0;
    for (std::size_t u = 0; u < values; ++u) *visited += model.kept(u * stride) ? 1 : 0;
  }
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
      for (std::size_t u = v0; u < v1; ++u) {
        const std::size_t v = u * stride;
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

InterpolationCheck check_interpolation(const Model& model, const MaterialSet& set, int most, ProgressSink& progress) {
  InterpolationCheck r;
  const int n = model.count();
  if (static_cast<int>(set.size()) != n || !(set.dims() == model.dims())) {
    r.note = "the source folder does not match the model (count or grid)";
    return r;
  }
  r.materials = spread_indices(n, most);
  const auto s = static_cast<Eigen::Index>(r.materials.size());
  const bool every = s == n;
  // m(x_i) = (1 - sum w) mean + sum_j w_j z_j with w = w(x_i), for the checked i at once: one
  // product (s x n by n x columns) per block of values, the blocks on the workers. Only the
  // checked materials' files are read; the model's stored values of all n are.
  Eigen::MatrixXd Wt(s, n);  // row k: w(x_i) of checked material i
  Eigen::VectorXd weight_of_mean(s);
  for (Eigen::Index k = 0; k < s; ++k) {
    const int i = r.materials[static_cast<std::size_t>(k)];
    const Eigen::VectorXd w = model.weights(model.latent().row(i).transpose());
    r.max_weight_error = std::max(r.max_weight_error, (w - Eigen::VectorXd::Unit(n, i)).cwiseAbs().maxCoeff());
    Wt.row(k) = w.transpose();
    weight_of_mean[k] = Combination::mean_weight(w);
  }
  const std::size_t values = set.value_count(), bins = set.dims().bins();
  constexpr std::size_t kBlock = 4096;
  const std::size_t blocks = (values + kBlock - 1) / kBlock;
  // Per block and checked material: its largest error, sum of errors and largest |value|, summed
  // in block order afterwards (the same bits whatever the workers' timing).
  Eigen::MatrixXd block_max(s, static_cast<Eigen::Index>(blocks)), block_sum(s, static_cast<Eigen::Index>(blocks)),
      block_peak(s, static_cast<Eigen::Index>(blocks));
  std::vector<std::size_t> block_counted(blocks, 0), block_mismatches(blocks, 0);
  ProgressTask task(progress, "checking exact interpolation", blocks);
  std::mutex progress_mutex;
  parallel_for(0, blocks, [&](std::size_t lo, std::size_t hi) {
    Eigen::MatrixXd z(n, static_cast<Eigen::Index>(kBlock)), rec(s, static_cast<Eigen::Index>(kBlock));
    Eigen::MatrixXd source(s, static_cast<Eigen::Index>(kBlock));  // the checked files, physical units
    Eigen::RowVectorXd mean(static_cast<Eigen::Index>(kBlock));
    std::vector<double> row(kBlock);
    std::vector<float> stored(static_cast<std::size_t>(n));
    std::vector<std::size_t> columns;  // the block's values checked (kept by the model and the files)
    for (std::size_t b = lo; b < hi; ++b) {
      const std::size_t v0 = b * kBlock, count = std::min(kBlock, values - v0);
      std::vector<std::uint8_t> measured(count, 1);  // by every checked file
      for (Eigen::Index k = 0; k < s; ++k) {
        set.file(static_cast<std::size_t>(r.materials[static_cast<std::size_t>(k)])).read_values(v0, count, row.data());
        for (std::size_t j = 0; j < count; ++j) {
          const std::size_t v = v0 + j;
          measured[j] &= static_cast<std::uint8_t>(row[j] >= 0.0);
          source(k, static_cast<Eigen::Index>(j)) = row[j] * BrdfTable::kChannelScale[v / bins];
        }
      }
      columns.clear();
      for (std::size_t j = 0; j < count; ++j) {
        const int c = model.column_of(v0 + j);
        // A value the model keeps must be measured by every file; with every material checked,
        // a value they all measure must be kept.
        if ((c >= 0 && !measured[j]) || (every && c < 0 && measured[j])) ++block_mismatches[b];
        if (c < 0 || !measured[j]) continue;
        const auto col = static_cast<std::size_t>(c);
        const auto at = static_cast<Eigen::Index>(columns.size());
        model.data(col, stored.data());  // float32 or float16 storage alike
        for (int i = 0; i < n; ++i) z(i, at) = stored[static_cast<std::size_t>(i)];
        mean(at) = model.mean(col);
        columns.push_back(j);
      }
      const auto cols = static_cast<int>(columns.size());
      if (cols > 0) {
        blas::openblas().dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, static_cast<int>(s), cols, n, 1.0, Wt.data(),
                               static_cast<int>(s), z.data(), n, 0.0, rec.data(), static_cast<int>(s));
        rec.leftCols(cols).noalias() += weight_of_mean * mean.head(cols);
      }
      for (Eigen::Index k = 0; k < s; ++k) {
        double most_error = 0, sum = 0, peak = 0;
        for (int a = 0; a < cols; ++a) {
          const double zv = source(k, static_cast<Eigen::Index>(columns[static_cast<std::size_t>(a)]));
          const double e = std::abs(rec(k, a) - zv);
          most_error = std::max(most_error, e);
          sum += e;
          peak = std::max(peak, std::abs(zv));
        }
        block_max(k, static_cast<Eigen::Index>(b)) = most_error;
        block_sum(k, static_cast<Eigen::Index>(b)) = sum;
        block_peak(k, static_cast<Eigen::Index>(b)) = peak;
      }
      block_counted[b] = columns.size();
      std::lock_guard lock(progress_mutex);
      task.advance();
    }
  });
  r.available = true;
  std::size_t counted = 0;
  for (std::size_t b = 0; b < blocks; ++b) counted += block_counted[b], r.column_mismatches += block_mismatches[b];
  for (Eigen::Index k = 0; k < s; ++k) {
    double sum = 0;
    for (std::size_t b = 0; b < blocks; ++b) sum += block_sum(k, static_cast<Eigen::Index>(b));
    const double most_error = blocks ? block_max.row(k).maxCoeff() : 0.0, peak = blocks ? block_peak.row(k).maxCoeff() : 0.0;
    r.max_abs_error.push_back(most_error);
    r.mean_abs_error.push_back(counted ? sum / static_cast<double>(counted) : 0.0);
    r.max_relative_error.push_back(peak > 0 ? most_error / peak : 0.0);
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
  std::vector<Eigen::MatrixXd> input_albedo;  // [angle]: n x 3
  for (double deg : check.angles_degrees)
    input_albedo.push_back(inputs_signed_albedo(model, deg * kPi / 180.0, options.albedo_quadrature));
  task.advance(static_cast<std::uint64_t>(n));
  for (std::size_t p = 0; p < points.size(); ++p) {
    const Eigen::VectorXd w = model.weights(points[p]);
    const Eigen::VectorXd c = Combination(w).affine();
    const BrdfTable clamped = export_table(model, w);
    const std::vector<Rgb> curve = model.albedo_curve(w);
    for (std::size_t k = 0; k < angle_index.size(); ++k) {
      const double theta = check.angles_degrees[k] * kPi / 180.0;
      Rgb expected = Rgb::Zero();
      for (int i = 0; i < n; ++i) expected += c(i) * input_albedo[k].row(i).transpose().array();
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
  // The grid in serpentine order (odd rows right to left), so that the batch's convex solves
  // start from a neighbour's (Model::predict_batch); the same weights as point by point.
  Eigen::MatrixXd path(static_cast<Eigen::Index>(res) * rows, model.dim());
  std::vector<Eigen::Index> cell_of_step;
  for (int yi = 0; yi < rows; ++yi)
    for (int k = 0; k < res; ++k) {
      const int xi = yi % 2 ? res - 1 - k : k;
      Eigen::VectorXd x = centre;
      x(map.axis_x) = map.x_min + (xi + 0.5) / res * (map.x_max - map.x_min);
      if (model.dim() > 1) x(map.axis_y) = map.y_min + (yi + 0.5) / rows * (map.y_max - map.y_min);
      path.row(static_cast<Eigen::Index>(cell_of_step.size())) = x.transpose();
      cell_of_step.push_back(static_cast<Eigen::Index>(yi) * res + xi);
    }
  progress.message("plausibility map: " + std::to_string(path.rows()) + " grid points");
  const Model::Prediction predicted = model.predict_batch(path, model.interpolation());
  Eigen::MatrixXd W(n, path.rows());
  Eigen::VectorXd variance(path.rows());
  for (std::size_t step = 0; step < cell_of_step.size(); ++step) {
    W.col(cell_of_step[step]) = predicted.weights.col(static_cast<Eigen::Index>(step));
    variance[cell_of_step[step]] = predicted.variance[static_cast<Eigen::Index>(step)];
  }
  const std::size_t cells = cell_of_step.size();
  const std::vector<std::size_t> negatives = count_possible_negatives(model, W, count_negative_inputs(model)).negatives;
  map.values = model.kept_columns();
  std::size_t worst = 0;
  for (std::size_t k = 0; k < cells; ++k) {
    const double frac = map.values ? static_cast<double>(negatives[k]) / static_cast<double>(map.values) : 0.0;
    map.negative_fraction.push_back(frac);
    double most = 0;
    for (const Rgb& a : model.albedo_curve(W.col(static_cast<Eigen::Index>(k)))) most = std::max(most, a.maxCoeff());
    map.max_albedo.push_back(most);
    map.variance.push_back(variance[static_cast<Eigen::Index>(k)]);
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
  if (sources) out.interpolation = check_interpolation(model, *sources, options.interpolation_materials, progress);
  else out.interpolation.note = "source tables not available (pass the input folder or keep the files listed in the model)";

  const std::vector<Eigen::VectorXd> points = sample_points(model, options.sample_points, options.seed);

  out.reciprocity = check_reciprocity(model, points, options, progress);
  out.albedo = check_albedo(model, points, options, progress);
  out.map = plausibility_map(model, options, progress);
  return out;
}

}  // namespace matlas::eval
