#include "formats/rgl_sample_fit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "brdf/albedo.h"
#include "core/check.h"
#include "core/parallel.h"

namespace matlas {

namespace {

/// One point (a bin centre or a corner between bins) as a row of the least-squares problem: the
/// file's value there is a * sum over the two elevations (weights 1 - w1, w1) of the bilinear
/// interpolation of the cell at `corner` (position s, t), weighted by cos(theta_i) cos(theta_o) as
/// the target is. The sample grid's `corner` index (y * nx + x) is the same in every slice.
struct Observation {
  std::uint32_t corner = 0;
  float s = 0, t = 0, w1 = 0;
  float a = 0;
  std::array<float, 3> target{};
};

constexpr std::size_t kBlock = 4096;
/// The albedo rows weigh a channel's relative error against max(albedo, this): a dark channel
/// (a yellow's blue, albedo 0.02) pushed as hard as a bright one drove its samples below 0, and
/// holding them there raised its albedo instead (cg_sunflower's blue 0.78 -> 2.31 % off with a
/// floor of 0.01).
constexpr double kAlbedoFloor = 0.05;

class SampleProblem {
public:
  SampleProblem(const RglBsdf& file, const BrdfTable& table, std::size_t slices, bool corners)
      : nx_(file.reflectance_nx()), grid_(file.reflectance_nx() * file.reflectance_ny()), slices_(slices) {
    const MerlDims& dims = table.dims();
    // Rows per theta_h bin in parallel, then grouped by the lower elevation in bin order.
    std::vector<std::vector<std::pair<std::size_t, Observation>>> rows(static_cast<std::size_t>(dims.theta_h));
    const auto observe = [&](std::size_t row, const DirectionPair& d, const Rgb& value) {
      const RglBsdf::ReflectanceLookup l = file.reflectance_lookup(d.wi, d.wo);
      if (!l.valid) return;
      MATLAS_CHECK(l.blend.count == 2 && l.blend.slice[1] == l.blend.slice[0] + 1,
                   "the sample fit needs an isotropic file with two or more elevations");
      const RglWarp2D::Cell c = file.reflectance_cell(l);
      const double weight = d.wi.z() * d.wo.z();
      Observation o;
      o.corner = static_cast<std::uint32_t>(c.py * nx_ + c.px);
      o.s = static_cast<float>(c.s), o.t = static_cast<float>(c.t);
      o.w1 = static_cast<float>(l.blend.weight[1]);
      // f_file = scale * interpolated / cos(theta_o); weighted by cos(theta_i) cos(theta_o).
      o.a = static_cast<float>(l.scale * d.wi.z());
      for (int ch = 0; ch < 3; ++ch) o.target[static_cast<std::size_t>(ch)] = static_cast<float>(weight * std::max(value[ch], 0.0));
      rows[row].emplace_back(l.blend.slice[0], o);
    };
    parallel_for_each(0, rows.size(), [&](std::size_t i) {
      for (int j = 0; j < dims.theta_d; ++j)
        for (int k = 0; k < dims.phi_d; ++k) {
          // The bin's centre: the table's value.
          bool all = true;
          const Rgb value = table.bin_rgb(dims.flat(static_cast<int>(i), j, k), &all);
          const DirectionPair d = from_half_diff(bin_centre(dims, static_cast<int>(i), j, k));
          if (all && d.wi.z() > 0 && d.wo.z() > 0) observe(i, d, value);
          // The corner where this bin and the seven after it meet: the table's smooth lookup
          // (the mean of the eight), so that the fit follows the table between the centres too.
          if (!corners || static_cast<int>(i) + 1 >= dims.theta_h || j + 1 >= dims.theta_d) continue;
          for (int di = 0; di < 2 && all; ++di)
            for (int dj = 0; dj < 2 && all; ++dj)
              for (int dk = 0; dk < 2 && all; ++dk)
                table.bin_rgb(dims.flat(static_cast<int>(i) + di, j + dj, (k + dk) % dims.phi_d), &all);
          if (!all) continue;
          HalfDiffAngles a;
          const double u = static_cast<double>(i + 1) / dims.theta_h;
          a.theta_h = u * u * (kPi / 2.0);
          a.theta_d = static_cast<double>(j + 1) / dims.theta_d * (kPi / 2.0);
          a.phi_d = static_cast<double>(k + 1) / dims.phi_d * kPi;
          const DirectionPair e = from_half_diff(a);
          if (e.wi.z() > 0 && e.wo.z() > 0) observe(i, e, table.lookup_smooth(e.wi, e.wo));
        }
    });
    std::vector<std::size_t> count(slices_, 0);
    for (const auto& row : rows)
      for (const auto& [g, o] : row) ++count[g];
    start_.assign(slices_ + 1, 0);
    for (std::size_t g = 0; g < slices_; ++g) start_[g + 1] = start_[g] + count[g];
    observations_.resize(start_.back());
    std::vector<std::size_t> next(start_.begin(), start_.end() - 1);
    for (const auto& row : rows)
      for (const auto& [g, o] : row) observations_[next[g]++] = o;
  }

  std::size_t observations() const { return observations_.size(); }
  std::size_t grid() const { return grid_; }
  std::size_t unknowns() const { return slices_ * 3 * grid_; }

  /// r = b - M x (b the targets), [observation][channel], single precision (the residuals are
  /// needed to a few digits, and they are the largest vectors).
  void residual(const std::vector<double>& x, std::vector<float>& r) const {
    forward(x, r);
    parallel_for_blocks(observations_.size(), kBlock, [&](std::size_t first, std::size_t size) {
      for (std::size_t o = first; o < first + size; ++o)
        for (std::size_t c = 0; c < 3; ++c) r[3 * o + c] = observations_[o].target[c] - r[3 * o + c];
    });
    const std::size_t n = observations_.size();
    for (std::size_t j = 0; j < albedo_rows_.size(); ++j)
      for (std::size_t c = 0; c < 3; ++c)
        r[3 * (n + j) + c] = static_cast<float>(albedo_rows_[j].target[c] - r[3 * (n + j) + c]);
  }

  /// Rows for the file's directional albedo at the elevations `views` (the view as the file's
  /// first direction, as a renderer integrates it: a half-vector quadrature of eval_cosine),
  /// against the table's by the same quadrature. Each channel's row is weighted so that a relative
  /// albedo error e costs weight e^2 / rows of that channel's targets' sum of squares: a renderer
  /// integrates the file, and the points alone leave its albedo a little off between elevations
  /// where the table's reflection changes fast with the angle (a pearlescent's colour shift).
  void add_albedo_rows(const RglBsdf& file, const BrdfTable& table, const std::vector<double>& views, double weight,
                       int resolution) {
    const std::array<double, 3> norms = target_norms();
    albedo_rows_.resize(views.size());
    parallel_for_each(0, views.size(), [&](std::size_t j) {
      const Vec3 view(std::sin(views[j]), 0.0, std::cos(views[j]));
      AlbedoRow& row = albedo_rows_[j];
      row.weight.assign(2 * grid_, 0.0);
      bool first = true;
      // half_vector_albedo's quadrature (brdf/albedo.h), its terms kept apart: the albedo is the
      // sum of eval_cosine(view, w) share / cos(theta_w).
      visit_half_vector_quadrature(view, resolution, [&](const Vec3& w, double share) {
        const RglBsdf::ReflectanceLookup l = file.reflectance_lookup(view, w);
        if (!l.valid) return;
        if (first) row.slice0 = l.blend.slice[0], first = false;
        const RglWarp2D::Cell cell = file.reflectance_cell(l);
        const std::size_t corner = cell.py * nx_ + cell.px;
        const double k = l.scale * share / w.z();
        const std::array<double, 4> cw = cell.weights();
        const std::size_t offset[4] = {0, 1, nx_, nx_ + 1};
        for (int s = 0; s < 2; ++s) {
          const double ws = k * l.blend.weight[static_cast<std::size_t>(s)];
          for (std::size_t q = 0; q < 4; ++q) row.weight[static_cast<std::size_t>(s) * grid_ + corner + offset[q]] += ws * cw[q];
        }
      });
      const Rgb albedo = half_vector_albedo([&](const Vec3& wi, const Vec3& wo) { return table.lookup_smooth(wi, wo); },
                                            view, resolution);
      for (std::size_t ch = 0; ch < 3; ++ch) {
        const double a = albedo[static_cast<Eigen::Index>(ch)];
        row.scale[ch] = std::sqrt(weight * norms[ch] / static_cast<double>(views.size())) / std::max(a, kAlbedoFloor);
        row.target[ch] = row.scale[ch] * std::max(a, 0.0);
      }
    });
  }
  /// Per channel sum of squares of the targets.
  std::array<double, 3> target_norms() const {
    std::array<double, 3> sum{0.0, 0.0, 0.0};
    for (const Observation& o : observations_)
      for (std::size_t c = 0; c < 3; ++c) sum[c] += static_cast<double>(o.target[c]) * o.target[c];
    return sum;
  }

  /// q = M x, [observation][channel].
  void forward(const std::vector<double>& x, std::vector<float>& q) const {
    q.resize(3 * (observations_.size() + albedo_rows_.size()));
    parallel_for_blocks(observations_.size(), kBlock, [&](std::size_t first, std::size_t size) {
      for (std::size_t g = group_of(first), o = first; o < first + size; ++o) {
        while (o >= start_[g + 1]) ++g;
        const Observation& ob = observations_[o];
        const auto w = corner_weights(ob);
        for (std::size_t c = 0; c < 3; ++c) {
          double sum = 0;
          for (std::size_t b = 0; b < 2; ++b) {
            const double* slice = x.data() + ((g + b) * 3 + c) * grid_ + ob.corner;
            const double wb = b ? ob.w1 : 1.0 - static_cast<double>(ob.w1);
            sum += wb * (w[0] * slice[0] + w[1] * slice[1] + w[2] * slice[nx_] + w[3] * slice[nx_ + 1]);
          }
          q[3 * o + c] = static_cast<float>(ob.a * sum);
        }
      }
    });
    const std::size_t n = observations_.size();
    q.resize(3 * (n + albedo_rows_.size()));
    for (std::size_t j = 0; j < albedo_rows_.size(); ++j) {
      const AlbedoRow& row = albedo_rows_[j];
      for (std::size_t c = 0; c < 3; ++c) {
        double sum = 0;
        for (std::size_t b = 0; b < 2; ++b) {
          const double* slice = x.data() + ((row.slice0 + b) * 3 + c) * grid_;
          const double* w = row.weight.data() + b * grid_;
          for (std::size_t k = 0; k < grid_; ++k) sum += w[k] * slice[k];
        }
        q[3 * (n + j) + c] = static_cast<float>(row.scale[c] * sum);
      }
    }
  }

  /// s = M^T r: the groups of one parity at a time, in parallel (a group writes its two slices).
  void transpose(const std::vector<float>& r, std::vector<double>& s) const {
    s.assign(unknowns(), 0.0);
    for (std::size_t parity = 0; parity < 2; ++parity) {
      const std::size_t groups = (slices_ + 1 - parity) / 2;
      parallel_for_each(0, groups, [&](std::size_t k) {
        const std::size_t g = 2 * k + parity;
        if (g + 1 >= slices_) return;  // no bin has its lower elevation at the last one
        for (std::size_t o = start_[g]; o < start_[g + 1]; ++o) {
          const Observation& ob = observations_[o];
          const auto w = corner_weights(ob);
          for (std::size_t c = 0; c < 3; ++c) {
            const double v = ob.a * r[3 * o + c];
            for (std::size_t b = 0; b < 2; ++b) {
              double* slice = s.data() + ((g + b) * 3 + c) * grid_ + ob.corner;
              const double wv = (b ? ob.w1 : 1.0 - static_cast<double>(ob.w1)) * v;
              slice[0] += w[0] * wv, slice[1] += w[1] * wv;
              slice[nx_] += w[2] * wv, slice[nx_ + 1] += w[3] * wv;
            }
          }
        }
      });
    }
    const std::size_t n = observations_.size();
    for (std::size_t j = 0; j < albedo_rows_.size(); ++j) {
      const AlbedoRow& row = albedo_rows_[j];
      for (std::size_t c = 0; c < 3; ++c) {
        const double v = row.scale[c] * r[3 * (n + j) + c];
        for (std::size_t b = 0; b < 2; ++b) {
          double* slice = s.data() + ((row.slice0 + b) * 3 + c) * grid_;
          const double* w = row.weight.data() + b * grid_;
          for (std::size_t k = 0; k < grid_; ++k) slice[k] += w[k] * v;
        }
      }
    }
  }

  /// The mean of the normal matrix's diagonal over the samples some observation reaches (the same
  /// for every channel): the scale of the damping.
  double mean_diagonal() const {
    std::vector<double> d(slices_ * grid_, 0.0);
    for (std::size_t g = 0; g + 1 < slices_; ++g)
      for (std::size_t o = start_[g]; o < start_[g + 1]; ++o) {
        const Observation& ob = observations_[o];
        const auto w = corner_weights(ob);
        for (std::size_t b = 0; b < 2; ++b) {
          const double wb = (b ? ob.w1 : 1.0 - static_cast<double>(ob.w1)) * ob.a;
          double* slice = d.data() + (g + b) * grid_ + ob.corner;
          slice[0] += (w[0] * wb) * (w[0] * wb), slice[1] += (w[1] * wb) * (w[1] * wb);
          slice[nx_] += (w[2] * wb) * (w[2] * wb), slice[nx_ + 1] += (w[3] * wb) * (w[3] * wb);
        }
      }
    double sum = 0;
    std::size_t count = 0;
    for (double v : d)
      if (v > 0) sum += v, ++count;
    return count ? sum / static_cast<double>(count) : 0.0;
  }

private:
  static std::array<double, 4> corner_weights(const Observation& o) { return RglWarp2D::Cell{0, 0, o.s, o.t}.weights(); }
  std::size_t group_of(std::size_t o) const {
    return static_cast<std::size_t>(std::upper_bound(start_.begin(), start_.end(), o) - start_.begin()) - 1;
  }

  /// A row of the albedo at one view elevation: weights over the samples of its two slices (the
  /// same for every channel), and per channel the row's weight and its weighted target.
  struct AlbedoRow {
    std::size_t slice0 = 0;
    std::vector<double> weight;
    std::array<double, 3> scale{}, target{};
  };

  std::size_t nx_, grid_, slices_;
  std::vector<AlbedoRow> albedo_rows_;
  std::vector<Observation> observations_;
  std::vector<std::size_t> start_;  ///< observations of group g: [start_[g], start_[g + 1])
};

/// Per channel sum of squares of a [item][channel] vector (observations) in fixed blocks.
std::array<double, 3> observation_norms(const std::vector<float>& v, std::size_t count = 0) {
  const std::size_t n = count ? count : v.size() / 3, blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::array<double, 3>> partial(blocks, {0.0, 0.0, 0.0});
  parallel_for_blocks(n, kBlock, [&](std::size_t first, std::size_t size) {
    std::array<double, 3>& p = partial[first / kBlock];
    for (std::size_t o = first; o < first + size; ++o)
      for (std::size_t c = 0; c < 3; ++c) p[c] += static_cast<double>(v[3 * o + c]) * v[3 * o + c];
  });
  std::array<double, 3> sum{0.0, 0.0, 0.0};
  for (const auto& p : partial)
    for (std::size_t c = 0; c < 3; ++c) sum[c] += p[c];
  return sum;
}

/// Calls f(channel, first, end) for each [slice][channel] run of `grid` unknowns.
template <class F>
void for_each_channel(std::size_t size, std::size_t grid, F&& f) {
  for (std::size_t first = 0, c = 0; first < size; first += grid, c = (c + 1) % 3) f(c, first, first + grid);
}

/// Per channel sum of squares of an unknowns vector laid out [slice][channel][grid].
std::array<double, 3> unknown_norms(const std::vector<double>& v, std::size_t grid) {
  std::array<double, 3> sum{0.0, 0.0, 0.0};
  for_each_channel(v.size(), grid, [&](std::size_t c, std::size_t first, std::size_t end) {
    for (std::size_t k = first; k < end; ++k) sum[c] += v[k] * v[k];
  });
  return sum;
}

double relative(const std::array<double, 3>& residual, const std::array<double, 3>& target) {
  const double total = target[0] + target[1] + target[2];
  return total > 0 ? std::sqrt((residual[0] + residual[1] + residual[2]) / total) : 0.0;
}

/// Conjugate gradients on the damped normal equations, min |b - M x|^2 + lambda |x - x0|^2 over
/// the samples not `fixed`, each channel its own problem (the same matrix), from x. Returns the
/// iterations run.
int damped_cg(const SampleProblem& problem, const std::vector<double>& x0, double lambda,
              const std::vector<std::uint8_t>& fixed, int iterations, std::vector<double>& x) {
  const std::size_t grid = problem.grid(), size = x.size();
  std::vector<float> q, r;
  std::vector<double> g, p;
  problem.residual(x, r);
  // The gradient's half: M^T r - lambda (x - x0), 0 where fixed.
  const auto gradient = [&](std::vector<double>& out) {
    problem.transpose(r, out);
    for (std::size_t k = 0; k < size; ++k) out[k] = fixed[k] ? 0.0 : out[k] - lambda * (x[k] - x0[k]);
  };
  gradient(g);
  p = g;
  std::array<double, 3> gamma = unknown_norms(g, grid);
  int it = 0;
  for (; it < iterations; ++it) {
    problem.forward(p, q);
    const std::array<double, 3> delta = observation_norms(q), pp = unknown_norms(p, grid);
    std::array<double, 3> alpha{};
    for (std::size_t c = 0; c < 3; ++c) {
      const double d = delta[c] + lambda * pp[c];
      alpha[c] = d > 0 ? gamma[c] / d : 0.0;
    }
    for_each_channel(size, grid, [&](std::size_t c, std::size_t first, std::size_t end) {
      for (std::size_t k = first; k < end; ++k) x[k] += alpha[c] * p[k];
    });
    const auto alpha_f = std::array<float, 3>{static_cast<float>(alpha[0]), static_cast<float>(alpha[1]),
                                              static_cast<float>(alpha[2])};
    for (std::size_t i = 0; i < r.size(); i += 3)
      for (std::size_t c = 0; c < 3; ++c) r[i + c] -= alpha_f[c] * q[i + c];
    gradient(g);
    const std::array<double, 3> next = unknown_norms(g, grid);
    for_each_channel(size, grid, [&](std::size_t c, std::size_t first, std::size_t end) {
      const double beta = gamma[c] > 0 ? next[c] / gamma[c] : 0.0;
      for (std::size_t k = first; k < end; ++k) p[k] = g[k] + beta * p[k];
    });
    gamma = next;
  }
  return it;
}

}  // namespace

RglSampleFitReport fit_rgl_samples(const RglBsdf& file, const BrdfTable& table, std::vector<float>& rgb,
                                   const RglSampleFitOptions& options) {
  MATLAS_CHECK(file.isotropic() && file.phi_i_count() <= 1 && file.theta_i_count() >= 2,
               "the sample fit needs an isotropic file with two or more elevations");
  const std::size_t nt = file.theta_i_count(), grid = file.reflectance_nx() * file.reflectance_ny();
  MATLAS_CHECK_EQ(rgb.size(), nt * 3 * grid);
  RglSampleFitReport report;
  SampleProblem problem(file, table, nt, options.corners);
  report.observations = problem.observations();
  std::vector<double> x(rgb.begin(), rgb.end());
  const std::array<double, 3> targets = problem.target_norms();
  if (options.albedo_weight > 0) {
    // At every elevation and midway between, to 85 deg.
    const std::vector<float>& nodes = file.theta_i();
    std::vector<double> views;
    for (std::size_t t = 0; t < nodes.size(); ++t) {
      if (nodes[t] <= 85.0 * kPi / 180.0) views.push_back(nodes[t]);
      const double mid = t + 1 < nodes.size() ? 0.5 * (static_cast<double>(nodes[t]) + nodes[t + 1]) : 10.0;
      if (mid <= 85.0 * kPi / 180.0) views.push_back(mid);
    }
    problem.add_albedo_rows(file, table, views, options.albedo_weight, options.albedo_resolution);
    report.albedo_rows = views.size();
  }

  const double lambda = options.damping * problem.mean_diagonal();
  const std::vector<double> x0 = x;
  std::vector<float> r;
  problem.residual(x, r);
  report.relative_rms_before = relative(observation_norms(r, problem.observations()), targets);
  // The normal-incidence slice keeps its point samples: a renderer sees it alone at theta_i = 0
  // (where the albedo at 0 deg comes from), while no bin centre lies there, so the fit would reach
  // it only through the interval above and bend it towards that interval's errors (the albedo at
  // 0 deg moved by up to 4 % on RGL's materials).
  std::vector<std::uint8_t> fixed(x.size(), 0);
  std::fill(fixed.begin(), fixed.begin() + static_cast<std::ptrdiff_t>(3 * grid), 1);
  report.iterations = damped_cg(problem, x0, lambda, fixed, options.iterations, x);
  // Samples the fit took below 0 are held at 0 and the others fitted again: clipping alone left
  // saturated colours (a channel near 0 over a highlight) farther from the table.
  std::size_t clipped = 0;
  for (std::size_t k = 0; k < x.size(); ++k)
    if (x[k] < 0) x[k] = 0, fixed[k] = 1, ++clipped;
  if (clipped > 0) report.iterations += damped_cg(problem, x0, lambda, fixed, options.iterations / 2, x);
  for (double& v : x) {
    if (v < 0) {
      v = 0;
      ++report.clipped;
    }
  }
  report.clipped += clipped;
  problem.residual(x, r);
  report.relative_rms_after = relative(observation_norms(r, problem.observations()), targets);
  for (std::size_t k = 0; k < x.size(); ++k) rgb[k] = static_cast<float>(x[k]);
  return report;
}

}  // namespace matlas
