// The acquisition functions of the `matlas` Python module (issue 30, docs/PYTHON.md): sparse
// measurements as numpy arrays fitted on a model (Model.fit_samples), the directions to measure
// (Model.sample_plan), and sample files read into arrays (read_samples, parse_samples).
// Directions are rows of (K, 3) arrays in the surface's frame (normal +z), values (K, 3) RGB.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "acquisition/model_samples.h"
#include "core/error.h"
#include "formats/sample_file.h"
#include "manifold/model.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace matlas {

py::array table_to_array(BrdfTable&& source, bool physical);  // python/module.cpp

namespace {

using Rows = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

std::string number_text(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

/// A (K, 3) array argument (a single row (3,) is K = 1); `what` names it in errors.
Rows rows_argument(const py::object& value, const std::string& what) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!a) throw py::value_error(what + " must be an array of numbers of shape (K, 3)");
  if (a.ndim() == 1 && a.shape(0) == 3) return Eigen::Map<const Rows>(a.data(), 1, 3);
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw py::value_error(what + " must have shape (K, 3), got " + std::string(py::str(py::tuple(py::cast(std::vector<py::ssize_t>(
                                                                   a.shape(), a.shape() + a.ndim()))))));
  return Eigen::Map<const Rows>(a.data(), a.shape(0), 3);
}

/// Uncertainties: None (unknown), a scalar, (K,) per sample or (K, 3) per channel.
Rows sigma_argument(const py::object& value, Eigen::Index K) {
  if (value.is_none()) return Rows::Zero(K, 3);
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!a) throw py::value_error("sigma must be None, a number, or an array of shape (K,) or (K, 3)");
  if (a.ndim() == 0) return Rows::Constant(K, 3, *a.data());
  if (a.ndim() == 1 && a.shape(0) == K) {
    Rows s(K, 3);
    for (Eigen::Index k = 0; k < K; ++k) s.row(k).setConstant(a.data()[k]);
    return s;
  }
  if (a.ndim() == 2 && a.shape(0) == K && a.shape(1) == 3) return Eigen::Map<const Rows>(a.data(), K, 3);
  throw py::value_error("sigma must be None, a number, or an array of shape (K,) or (K, 3) with K = " + std::to_string(K));
}

/// The samples of arrays, validated as a sample file's rows are (formats/sample_file.h), with
/// errors naming the row (0-based, as numpy indexes it) and raised as ValueError. A row whose
/// r, g, b are all NaN is a direction not measured yet (read_samples gives such rows).
std::vector<MeasuredSample> samples_argument(const py::object& wi_arg, const py::object& wo_arg, const py::object& rgb_arg,
                                             const py::object& sigma_arg, const std::string& quantity) {
  if (quantity != "brdf" && quantity != "ratio")
    throw py::value_error("quantity must be 'brdf' (f, 1/sr) or 'ratio' (f cos(theta_i)), got '" + quantity + "'");
  const Rows wi = rows_argument(wi_arg, "wi"), wo = rows_argument(wo_arg, "wo"), rgb = rows_argument(rgb_arg, "rgb");
  const Eigen::Index K = wi.rows();
  if (wo.rows() != K || rgb.rows() != K)
    throw py::value_error("wi, wo and rgb must have the same number of rows, got " + std::to_string(K) + ", " +
                          std::to_string(wo.rows()) + " and " + std::to_string(rgb.rows()));
  if (K == 0) throw py::value_error("no samples (the arrays have no rows)");
  const Rows sigma = sigma_argument(sigma_arg, K);
  std::vector<MeasuredSample> out;
  static const char* channels[3] = {"r", "g", "b"};
  for (Eigen::Index k = 0; k < K; ++k) {
    const std::string row = "row " + std::to_string(k) + ": ";
    MeasuredSample s;
    s.line = static_cast<int>(k);
    for (const auto& [v, name] : {std::pair{Vec3(wi.row(k).transpose()), "wi"}, std::pair{Vec3(wo.row(k).transpose()), "wo"}}) {
      if (!v.allFinite()) throw py::value_error(row + name + " is not finite");
      if (v.norm() == 0) throw py::value_error(row + name + " is the zero vector");
      if (v.z() / v.norm() <= 1e-9)
        throw py::value_error(row + name + " is at or below the horizon (z = " + number_text(v.z()) + ")");
    }
    s.wi = wi.row(k).transpose().normalized();
    s.wo = wo.row(k).transpose().normalized();
    const int missing = static_cast<int>(std::isnan(rgb(k, 0))) + std::isnan(rgb(k, 1)) + std::isnan(rgb(k, 2));
    if (missing == 3) {
      out.push_back(s);  // planned, not measured
      continue;
    }
    if (missing > 0) throw py::value_error(row + "r, g and b must all be given or all be NaN (not measured)");
    const double scale = quantity == "ratio" ? 1.0 / s.wi.z() : 1.0;
    for (int c = 0; c < 3; ++c) {
      const double v = rgb(k, c), e = sigma(k, c);
      if (!std::isfinite(v)) throw py::value_error(row + channels[c] + " is not finite");
      if (v < 0) throw py::value_error(row + channels[c] + " = " + number_text(v) + " is negative");
      if (!std::isfinite(e)) throw py::value_error(row + "sigma_" + channels[c] + " is not finite");
      if (e < 0) throw py::value_error(row + "sigma_" + channels[c] + " = " + number_text(e) + " is negative");
      s.value[c] = v * scale;
      s.sigma[c] = e * scale;
    }
    s.measured = true;
    out.push_back(s);
  }
  return out;
}

/// Messages of model_rows name a sample by its `line`, here the row.
std::vector<std::string> rows_named(std::vector<std::string> messages) {
  for (auto& m : messages)
    if (m.rfind("line ", 0) == 0) m.replace(0, 5, "row ");
  return messages;
}

py::dict fit_dict(const Model& model, const std::vector<MeasuredSample>& samples, bool robust) {
  // The rows measured, and for each its index among all rows.
  std::vector<MeasuredSample> measured;
  std::vector<Eigen::Index> index;
  for (std::size_t k = 0; k < samples.size(); ++k)
    if (samples[k].measured) {
      measured.push_back(samples[k]);
      index.push_back(static_cast<Eigen::Index>(k));
    }
  if (measured.empty()) throw py::value_error("no measured samples (every row's rgb is NaN)");
  acquisition::SparseFitOptions options;
  options.transform = acquisition::model_transform(model);
  options.robust = robust;
  acquisition::ModelFit fit;
  {
    py::gil_scoped_release release;
    fit = acquisition::fit_samples(model, measured, options);
  }
  const acquisition::SampleRows& rows = fit.rows;
  const acquisition::SparseFit& f = fit.fit;
  const auto K = static_cast<Eigen::Index>(samples.size());
  const double nan = std::nan("");
  Rows residual = Rows::Constant(K, 3, nan), predicted = Rows::Constant(K, 3, nan), weight = Rows::Constant(K, 3, nan);
  for (Eigen::Index r = 0; r < rows.rows() && r < f.residual.size(); ++r) {
    const Eigen::Index k = index[static_cast<std::size_t>(rows.sample[static_cast<std::size_t>(r)])];
    const int c = rows.channel[static_cast<std::size_t>(r)];
    residual(k, c) = f.residual[r];
    predicted(k, c) = f.predicted[r];
    weight(k, c) = f.weight[r];
  }
  std::vector<Eigen::Index> outliers;
  py::array_t<bool> is_outlier(K);
  auto flags = is_outlier.mutable_unchecked<1>();
  for (Eigen::Index k = 0; k < K; ++k) flags(k) = false;
  for (int o : f.outliers) {
    const Eigen::Index k = index[static_cast<std::size_t>(o)];
    outliers.push_back(k);
    flags(k) = true;
  }
  py::object best = py::none();
  if (f.best_input >= 0) best = py::str(model.names()[static_cast<std::size_t>(f.best_input)]);
  return py::dict("x"_a = f.x, "weights"_a = fit.weights, "coefficients"_a = f.coefficients, "variance"_a = f.variance,
                  "latent_covariance"_a = f.latent_covariance, "residual"_a = residual, "predicted"_a = predicted,
                  "weight"_a = weight, "outliers"_a = outliers, "is_outlier"_a = is_outlier, "best_input"_a = best,
                  "best_index"_a = f.best_input, "input_loss"_a = f.input_loss, "combined"_a = f.combined,
                  "map_coefficients"_a = f.map_coefficients, "combination_strength"_a = f.combination_strength, "loss"_a = f.loss, "scale"_a = f.scale,
                  "used"_a = static_cast<int>(rows.rows() / 3), "unusable"_a = rows_named(fit.unusable),
                  "transform"_a = options.transform.to_string(), "evaluations"_a = f.evaluations);
}


/// A sample file as arrays (what read_samples and parse_samples return).
py::dict file_dict(const SampleFile& file) {
  const auto K = static_cast<Eigen::Index>(file.samples.size());
  Rows wi(K, 3), wo(K, 3), rgb(K, 3), sigma(K, 3);
  py::array_t<bool> measured(K);
  py::array_t<int> line(K);
  auto m = measured.mutable_unchecked<1>();
  auto l = line.mutable_unchecked<1>();
  for (Eigen::Index k = 0; k < K; ++k) {
    const MeasuredSample& s = file.samples[static_cast<std::size_t>(k)];
    wi.row(k) = s.wi.transpose();
    wo.row(k) = s.wo.transpose();
    rgb.row(k) = s.measured ? Eigen::RowVector3d(s.value.transpose()) : Eigen::RowVector3d::Constant(std::nan(""));
    sigma.row(k) = s.sigma.transpose();
    m(k) = s.measured;
    l(k) = s.line;
  }
  return py::dict("wi"_a = wi, "wo"_a = wo, "rgb"_a = rgb, "sigma"_a = sigma, "measured"_a = measured, "line"_a = line,
                  "skipped"_a = file.skipped, "json"_a = file.json);
}

}  // namespace

void bind_acquisition(py::module_& m) {
  auto model = py::reinterpret_borrow<py::class_<Model>>(m.attr("Model"));
  model.def(
      "fit_samples",
      [](const Model& s, const py::object& wi, const py::object& wo, const py::object& rgb, const py::object& sigma,
         const std::string& quantity, bool robust) {
        return fit_dict(s, samples_argument(wi, wo, rgb, sigma, quantity), robust);
      },
      "wi"_a, "wo"_a, "rgb"_a, "sigma"_a = py::none(), "quantity"_a = "brdf", "robust"_a = true,
      "The map point that best explains sparse measurements (issue 30, docs/ACQUISITION.md).\n"
      "wi, wo: (K, 3) directions in the surface's frame (normal +z; normalised here; wi the light);\n"
      "rgb: (K, 3) values, BRDF f (quantity='brdf') or f cos(theta_i) (quantity='ratio'); a row of NaN\n"
      "is a direction not measured (ignored); sigma: None, a number, (K,) or (K, 3) uncertainties (0:\n"
      "unknown). robust: Cauchy loss (False: least squares), in the layout's space of the model.\n"
      "Returns a dict: x (q,), weights (n,) (Model.table_for_weights(weights) is the fitted table;\n"
      "Model.table(x) too unless combined: the combination stage found a convex mix of the inputs\n"
      "off the map that explains the samples better), combined, map_coefficients, coefficients,\n"
      "variance, latent_covariance (q, q), residual / predicted / weight (K, 3) per sample and\n"
      "channel (NaN for rows not fitted), outliers (row indices), is_outlier (K,), best_input\n"
      "(name), best_index, input_loss (n,), loss, scale, used, unusable, transform, evaluations.\n"
      "A row below the horizon, not finite or negative raises ValueError naming it; fewer usable\n"
      "samples than q + 1 raise matlas.Error.");
  model.def(
      "table_for_weights",
      [](const Model& s, const Eigen::VectorXd& w, bool physical) {
        if (w.size() != s.count() || !w.allFinite())
          throw py::value_error("weights must be " + std::to_string(s.count()) + " finite numbers (one per input)");
        BrdfTable t;
        {
          py::gil_scoped_release release;
          t = s.table(w);
        }
        return table_to_array(std::move(t), physical);
      },
      "weights"_a, "physical"_a = true,
      "The table of given weights over the inputs (as Model.weights returns, or fit_samples' weights,\n"
      "which are a combination of inputs off the map when its 'combined' is True): a (3, theta_h,\n"
      "theta_d, phi_d) array like Model.table.");
  model.def(
      "evaluate",
      [](const Model& s, const Eigen::VectorXd& x, const py::object& wi_arg, const py::object& wo_arg) {
        if (x.size() != s.dim() || !x.allFinite())
          throw py::value_error("x must be " + std::to_string(s.dim()) + " finite coordinates");
        const Rows wi = rows_argument(wi_arg, "wi"), wo = rows_argument(wo_arg, "wo");
        if (wi.rows() != wo.rows()) throw py::value_error("wi and wo must have the same number of rows");
        for (Eigen::Index k = 0; k < wi.rows(); ++k)
          if (!wi.row(k).allFinite() || !wo.row(k).allFinite() || wi.row(k).norm() == 0 || wo.row(k).norm() == 0)
            throw py::value_error("row " + std::to_string(k) + ": a direction is not finite or is the zero vector");
        const Eigen::VectorXd w = s.weights(x);
        Rows out(wi.rows(), 3);
        for (Eigen::Index k = 0; k < wi.rows(); ++k) {
          const Vec3 a = wi.row(k).transpose().normalized(), b = wo.row(k).transpose().normalized();
          out.row(k) = (a.z() > 0 && b.z() > 0) ? Eigen::RowVector3d(s.lookup(a, b, w).transpose()) : Eigen::RowVector3d::Zero();
        }
        return out;
      },
      "x"_a, "wi"_a, "wo"_a,
      "RGB f(wi, wo) of the table m(x) for rows of (K, 3) directions (normal +z), by MERL's nearest-bin\n"
      "lookup (the bins fit_samples reads): a (K, 3) array, 0 below the horizon and where no data is kept.");
  model.def(
      "sample_plan",
      [](const Model& s, int k, const py::object& measured) {
        if (k < 1 || k > 10000) throw py::value_error("k must be in [1, 10000], got " + std::to_string(k));
        std::vector<MeasuredSample> given;
        if (!measured.is_none()) {
          if (!py::isinstance<py::dict>(measured))
            throw py::value_error("measured must be None or a dict with wi, wo, rgb (and optionally sigma, quantity), "
                                  "as read_samples returns");
          const py::dict d = measured.cast<py::dict>();
          for (const char* key : {"wi", "wo", "rgb"})
            if (!d.contains(key)) throw py::value_error(std::string("measured has no '") + key + "'");
          given = samples_argument(d["wi"], d["wo"], d["rgb"], d.contains("sigma") ? py::object(d["sigma"]) : py::none(),
                                   d.contains("quantity") ? d["quantity"].cast<std::string>() : std::string("brdf"));
        }
        acquisition::PlanOptions options;
        options.transform = acquisition::model_transform(s);
        options.rank = std::max(1, std::min(options.rank, s.count() - 1));
        acquisition::ModelPlan plan;
        {
          py::gil_scoped_release release;
          plan = acquisition::plan_samples(s, k, given, options);
        }
        const auto K = static_cast<Eigen::Index>(plan.directions.size());
        Rows wi(K, 3), wo(K, 3);
        Eigen::MatrixXd theta_phi(K, 4);
        for (Eigen::Index r = 0; r < K; ++r) {
          const MeasuredSample& d = plan.directions[static_cast<std::size_t>(r)];
          wi.row(r) = d.wi.transpose();
          wo.row(r) = d.wo.transpose();
          const auto [ti, pi] = direction_angles(d.wi);
          const auto [to, po] = direction_angles(d.wo);
          theta_phi.row(r) << ti, pi, to, po;
        }
        return py::dict("wi"_a = wi, "wo"_a = wo, "theta_i"_a = Eigen::VectorXd(theta_phi.col(0)),
                        "phi_i"_a = Eigen::VectorXd(theta_phi.col(1)), "theta_o"_a = Eigen::VectorXd(theta_phi.col(2)),
                        "phi_o"_a = Eigen::VectorXd(theta_phi.col(3)), "gain"_a = plan.plan.gain,
                        "remaining"_a = plan.plan.remaining, "conditioned_on"_a = plan.conditioned_on,
                        "csv"_a = format_samples_csv(plan.directions, {"matlas sample plan: " + std::to_string(K) +
                                                                        " directions"}));
      },
      "k"_a, "measured"_a = py::none(),
      "The k directions to measure for this map: a greedy information-gain design over the inputs\n"
      "(docs/ACQUISITION.md); given `measured` (a dict with wi, wo, rgb, as read_samples returns), the\n"
      "next directions after those samples. Returns a dict: wi, wo (k, 3), theta_i, phi_i, theta_o,\n"
      "phi_o (k,) in degrees, gain (k,) nats, remaining, conditioned_on, and csv (the plan as a sample\n"
      "file with empty values, as `matlas sample-plan` writes it).");
  m.def(
      "read_samples",
      [](const std::filesystem::path& path, bool skip_invalid) {
        SampleReadOptions o;
        o.skip_invalid = skip_invalid;
        return file_dict(read_samples(path, o));
      },
      "path"_a, "skip_invalid"_a = false,
      "Reads a sample file (CSV or JSON, docs/ACQUISITION.md) as arrays: a dict with wi, wo (K, 3) unit\n"
      "directions, rgb (K, 3) BRDF values (NaN for directions not measured), sigma (K, 3) (0: unknown),\n"
      "measured (K,) bool, line (K,) (the file's line, or JSON sample number), skipped (invalid rows,\n"
      "with skip_invalid=True; otherwise they raise matlas.Error naming their lines), json.");
  m.def("parse_samples",
        [](const std::string& text, const std::string& name, bool skip_invalid) {
          SampleReadOptions o;
          o.skip_invalid = skip_invalid;
          return file_dict(parse_samples(text, name, o));
        },
        "text"_a, "name"_a = "samples", "skip_invalid"_a = false,
        "read_samples() of text in memory; `name` stands for the file in messages.");
}

}  // namespace matlas
