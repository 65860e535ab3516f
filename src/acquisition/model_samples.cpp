#include "acquisition/model_samples.h"

#include <algorithm>
#include <string>

#include "core/check.h"
#include "core/combination.h"
#include "core/error.h"
#include "manifold/model_metadata.h"

namespace matlas::acquisition {

LayoutTransform model_transform(const Model& model) {
  const auto& meta = model.metadata();
  const auto it = meta.find("layout_transform");
  if (it == meta.end() || !it->is_string()) return LayoutTransform{LayoutTransform::Map::cube_root, true};
  return LayoutTransform::parse(it->get<std::string>());
}

namespace {

/// The inputs' values at one bin, 3 x n; false when a channel is not kept.
bool bin_values(const Model& model, std::size_t bin, Eigen::MatrixXd& out) {
  const std::size_t bins = model.dims().bins();
  MATLAS_DCHECK_LT(bin, bins);
  const int n = model.count();
  out.resize(3, n);
  std::vector<float> buffer(static_cast<std::size_t>(n));
  for (int c = 0; c < 3; ++c) {
    const int column = model.column_of(static_cast<std::size_t>(c) * bins + bin);
    if (column < 0) return false;
    model.data(static_cast<std::size_t>(column), buffer.data());
    for (int i = 0; i < n; ++i) out(c, i) = buffer[static_cast<std::size_t>(i)];
  }
  return true;
}

}  // namespace

SampleRows model_rows(const Model& model, const std::vector<MeasuredSample>& samples, std::vector<std::string>* unusable) {
  SampleRows rows;
  rows.inputs.resize(0, model.count());
  Eigen::MatrixXd values;
  for (std::size_t s = 0; s < samples.size(); ++s) {
    const MeasuredSample& m = samples[s];
    if (!bin_values(model, bin_of(model.dims(), m.wi, m.wo), values)) {
      if (unusable) unusable->push_back("line " + std::to_string(m.line) + ": the model has no data at this direction");
      continue;
    }
    rows.add(static_cast<int>(s), values, m.value, m.sigma, m.wi.z() * m.wo.z());
  }
  return rows;
}

MapView model_map(const Model& model) {
  MapView map;
  map.latent = model.latent();
  map.coefficients = [&model](const Eigen::VectorXd& x) { return Combination(model.weights(x)).affine(); };
  map.variance = [&model](const Eigen::VectorXd& x) { return model.variance(x); };
  map.metric = model.convex_metric();
  return map;
}

ModelFit fit_samples(const Model& model, const std::vector<MeasuredSample>& samples, const SparseFitOptions& options) {
  std::vector<MeasuredSample> measured;
  for (const auto& s : samples)
    if (s.measured) measured.push_back(s);
  if (measured.empty()) throw Error("no measured samples (every row's r, g, b is empty)");
  ModelFit out;
  out.rows = model_rows(model, measured, &out.unusable);
  out.fit = fit_rows(model_map(model), out.rows, options);
  // A combination's raw coefficients sum to 1: as the model's weights they give the same table in
  // either mode (m = (1 - sum w) mean + sum w_i z_i).
  out.weights = out.fit.combined ? out.fit.coefficients : model.weights(out.fit.x);
  // Report samples by their own indices in `samples`, not the measured subset's.
  std::vector<int> index;
  for (std::size_t s = 0; s < samples.size(); ++s)
    if (samples[s].measured) index.push_back(static_cast<int>(s));
  MATLAS_CHECK_EQ(out.weights.size(), Eigen::Index{model.count()});
  for (int& o : out.fit.outliers) {
    MATLAS_CHECK(o >= 0 && static_cast<std::size_t>(o) < index.size(), "an outlier is one of the measured samples");
    o = index[static_cast<std::size_t>(o)];
  }
  return out;
}

ModelPlan plan_samples(const Model& model, int count, const std::vector<MeasuredSample>& measured,
                       const PlanOptions& options) {
  const PlanCandidates candidates = plan_candidates(model.dims());
  PlanSpace space;
  space.values.resize(3 * static_cast<Eigen::Index>(candidates.bins.size()), model.count());
  space.cosine.resize(static_cast<Eigen::Index>(candidates.bins.size()));
  Eigen::MatrixXd values;
  std::vector<std::size_t> usable;
  for (std::size_t c = 0; c < candidates.bins.size(); ++c) {
    if (!bin_values(model, candidates.bins[c], values)) continue;
    const auto row = static_cast<Eigen::Index>(usable.size());
    space.values.middleRows(3 * row, 3) = values;
    space.cosine(row) = candidates.directions[c].wi.z() * candidates.directions[c].wo.z();
    usable.push_back(c);
  }
  const auto C = static_cast<Eigen::Index>(usable.size());
  if (C == 0) throw Error(model.path().string() + ": the model has no data at any candidate direction");
  space.values.conservativeResize(3 * C, Eigen::NoChange);
  space.cosine.conservativeResize(C);

  ModelPlan out;
  Eigen::VectorXd weight = Eigen::VectorXd::Ones(model.count());
  SampleRows rows;
  std::vector<MeasuredSample> with_values;
  for (const auto& s : measured)
    if (s.measured) with_values.push_back(s);
  if (!with_values.empty()) {
    rows = model_rows(model, with_values);
    out.conditioned_on = static_cast<int>(with_values.size());
    if (static_cast<int>(with_values.size()) >= model.dim() + 1) {
      SparseFitOptions fo;
      fo.transform = options.transform;
      const SparseFit fit = fit_rows(model_map(model), rows, fo);
      weight = plausible_inputs(fit.input_loss, std::max(model.count() / 4.0, 2.0 * model.dim() + 2));
    }
  }
  std::vector<int> excluded;
  for (const auto& s : with_values) {
    const std::size_t bin = bin_of(model.dims(), s.wi, s.wo);
    for (std::size_t c = 0; c < usable.size(); ++c)
      if (candidates.bins[usable[c]] == bin) excluded.push_back(static_cast<int>(c));
  }
  out.plan = plan_directions(space, weight, rows.rows() > 0 ? &rows : nullptr, count, options, excluded);
  for (std::size_t k = 0; k < out.plan.chosen.size(); ++k) {
    MeasuredSample s = candidates.directions[usable[static_cast<std::size_t>(out.plan.chosen[k])]];
    s.line = static_cast<int>(k) + 1;
    out.directions.push_back(s);
  }
  return out;
}

}  // namespace matlas::acquisition
