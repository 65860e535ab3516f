// The `matlas` Python module (pybind11): models, building, MERL/RGL files and the evaluation's
// distances (sparse samples: python/acquisition.cpp). Tables cross the boundary as float64 numpy
// arrays of shape (3, theta_h, theta_d, phi_d), channel-major like MERL files: physical values
// with NaN where nothing was measured (default), or MERL's stored units with -1 (physical=False),
// bit-exact with the files.
// python/matlas/__init__.pyi documents the API.
#include <chrono>
#include <cstdio>
#include <cmath>
#include <exception>
#include <mutex>
#include <optional>
#include <unistd.h>

#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "core/blas.h"
#include "core/error.h"
#include "eval/brdf_distance.h"
#include "formats/merl_file.h"
#include "formats/rgl_bsdf.h"
#include "manifold/build.h"
#include "manifold/model_metadata.h"
#include "manifold/project.h"

namespace py = pybind11;
using namespace pybind11::literals;
namespace fs = std::filesystem;

namespace matlas {

void bind_acquisition(py::module_& m);  // python/acquisition.cpp

/// Hands a table to numpy without copying: the array owns the table through a capsule. With
/// `physical`, values are converted in place (missing -> NaN). Also used by python/acquisition.cpp.
py::array table_to_array(BrdfTable&& source, bool physical) {
  auto* t = new BrdfTable(std::move(source));
  py::capsule owner(t, [](void* p) { delete static_cast<BrdfTable*>(p); });
  if (physical) {
    double* v = t->stored().data();
    const std::size_t bins = t->bins();
    for (int c = 0; c < 3; ++c) {
      const double scale = BrdfTable::kChannelScale[static_cast<std::size_t>(c)];
      double* block = v + static_cast<std::size_t>(c) * bins;
      for (std::size_t b = 0; b < bins; ++b) block[b] = block[b] < 0.0 ? std::nan("") : block[b] * scale;
    }
  }
  const MerlDims d = t->dims();
  const auto s = static_cast<py::ssize_t>(sizeof(double));
  return py::array(py::dtype::of<double>(), {py::ssize_t{3}, py::ssize_t{d.theta_h}, py::ssize_t{d.theta_d}, py::ssize_t{d.phi_d}},
                   {s * d.theta_h * d.theta_d * d.phi_d, s * d.theta_d * d.phi_d, s * d.phi_d, s}, t->stored().data(), owner);
}

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// A (3, theta_h, theta_d, phi_d) array (or its flat 3 * bins form for the standard grid) as a
/// table. Physical values: NaN or negative means missing. Infinite values, and values beyond what
/// the MERL reader accepts (kMaxMerlMagnitude in stored units), are a ValueError naming the
/// channel and bin: write_merl must not write a file that read_merl refuses.
BrdfTable array_to_table(const Array& a, bool physical) {
  MerlDims dims;
  if (a.ndim() == 4 && a.shape(0) == 3) {
    dims = {static_cast<int>(a.shape(1)), static_cast<int>(a.shape(2)), static_cast<int>(a.shape(3))};
  } else if (a.ndim() == 1 && static_cast<std::size_t>(a.shape(0)) == 3 * MerlDims{}.bins()) {
    dims = MerlDims{};
  } else {
    std::string shape;
    for (py::ssize_t i = 0; i < a.ndim(); ++i) {
      if (i) shape += ", ";
      shape += std::to_string(a.shape(i));
    }
    throw py::value_error("a BRDF table has shape (3, theta_h, theta_d, phi_d), got (" + shape + ")");
  }
  if (dims.theta_h < 1 || dims.theta_d < 1 || dims.phi_d < 1) throw py::value_error("empty BRDF table");
  BrdfTable t(dims, ValueBuffer::Uninitialized{});
  const double* in = a.data();
  double* out = t.stored().data();
  const std::size_t bins = t.bins();
  for (int c = 0; c < 3; ++c) {
    const double scale = physical ? BrdfTable::kChannelScale[static_cast<std::size_t>(c)] : 1.0;
    for (std::size_t b = 0; b < bins; ++b) {
      const double v = in[static_cast<std::size_t>(c) * bins + b];
      if (std::isinf(v)) throw py::value_error("infinite value in the table (channel " + std::to_string(c) + ")");
      const double stored = (std::isnan(v) || v < 0.0) ? -1.0 : v / scale;
      if (!(stored <= kMaxMerlMagnitude)) {
        char text[32];
        std::snprintf(text, sizeof text, "%.6g", v);
        throw py::value_error(std::string("absurd value ") + text + " in the table (channel " + std::to_string(c) +
                              ", bin " + std::to_string(b) + "): beyond the magnitude read_merl accepts, 1e15 in "
                              "MERL's stored units (" + (physical ? "about 6.7e11 physical" : "physical=False") + ")");
      }
      out[static_cast<std::size_t>(c) * bins + b] = stored;
    }
  }
  return t;
}

Eigen::VectorXd point(const Model& m, const Eigen::Ref<const Eigen::VectorXd>& x) {
  if (x.size() != m.dim())
    throw py::value_error("the point has " + std::to_string(x.size()) + " coordinates, the model has q = " +
                          std::to_string(m.dim()));
  if (!x.allFinite()) throw py::value_error("the point has a NaN or infinite coordinate");
  return x;
}

void check_points(const Model& m, const Eigen::MatrixXd& X) {
  if (X.cols() != m.dim())
    throw py::value_error("points are rows of an (m, q) array; got " + std::to_string(X.cols()) +
                          " columns for q = " + std::to_string(m.dim()));
  for (Eigen::Index r = 0; r < X.rows(); ++r)
    if (!X.row(r).allFinite())
      throw py::value_error("the point of row " + std::to_string(r) + " has a NaN or infinite coordinate");
}

/// `result`, unless the model's file was truncated while it was read (its mapping read vanished
/// pages as zeros, formats/safetensors.h): then what was computed from it is wrong, and
/// matlas.Error names the file instead. Every function reading the model returns through this.
template <class T>
T intact(const Model& m, T&& result) {
  if (const std::uint64_t faults = m.mapping_faults(); faults > 0)
    throw file_error(m.path(), "the model file changed or was truncated while it was read (" + std::to_string(faults) +
                                   " pages read as zeros): open it again once it is complete");
  return std::forward<T>(result);
}

/// Forwards build progress to a Python callable progress(label, done, total), from whichever
/// thread reports, holding the GIL only for the call. The first exception it raises is kept and
/// rethrown when the build returns; later updates are dropped.
class PythonProgress final : public ProgressSink {
public:
  explicit PythonProgress(py::object callback) : callback_(std::move(callback)) {}
  ~PythonProgress() override {
    py::gil_scoped_acquire gil;
    callback_ = py::object();
  }
  void update(const std::string& label, std::uint64_t done, std::uint64_t total) override {
    std::lock_guard lock(mutex_);
    if (error_ || callback_.is_none()) return;
    py::gil_scoped_acquire gil;
    try {
      callback_(label, done, total);
    } catch (py::error_already_set&) {
      error_ = std::current_exception();
    }
  }
  void message(const std::string&) override {}
  void finish(const std::string&) override {}
  void rethrow() {
    if (error_) std::rethrow_exception(error_);
  }

private:
  py::object callback_;
  std::mutex mutex_;
  std::exception_ptr error_;
};

std::vector<fs::path> input_paths(const py::object& inputs) {
  std::vector<fs::path> paths;
  if (py::isinstance<py::str>(inputs) || py::hasattr(inputs, "__fspath__")) {
    paths.push_back(inputs.cast<fs::path>());
  } else {
    for (const auto& item : inputs) paths.push_back(item.cast<fs::path>());
  }
  return paths;
}

Model build(const py::object& inputs, const std::optional<fs::path>& output_arg, int dim, double nugget, const std::string& optimizer,
            const std::string& layout, const std::string& storage, int starts, int max_iterations, int coarse,
            int sparse_inducing, const py::object& progress) {
  BuildOptions o;
  o.dim = dim;
  o.nugget = nugget;
  o.layout = LayoutTransform::parse(layout);
  o.optimize.method = gp::optimizer_from_string(optimizer);
  o.optimize.max_iterations = max_iterations;
  o.optimize.starts = starts;  // 0: BuildOptions::default_starts
  o.optimize.coarse = coarse;
  o.sparse.inducing = sparse_inducing;
  if (storage == "f16") o.storage = Storage::f16;
  else if (storage != "f32") throw py::value_error("storage must be 'f32' or 'f16', got '" + storage + "'");
  const std::vector<fs::path> paths = input_paths(inputs);
  // Without an output, the model goes to a temporary file that is unlinked once mapped (the
  // mapping stays valid; nothing is left on disk).
  fs::path output;
  if (output_arg) {
    output = *output_arg;
  } else {
    std::error_code ec;
    fs::path dir = fs::temp_directory_path(ec);
    if (ec) dir = "/tmp";
    std::string name = (dir / "matlas-model-XXXXXX").string();
    const int fd = ::mkstemp(name.data());
    if (fd < 0) throw Error("cannot create a temporary model file in " + dir.string());
    ::close(fd);
    output = name;
  }
  struct Unlink {
    const fs::path* path;
    ~Unlink() {
      if (path) {
        std::error_code ec;
        fs::remove(*path, ec);
      }
    }
  } unlink_temporary{output_arg ? nullptr : &output};
  PythonProgress sink(progress);
  {
    py::gil_scoped_release release;
    const MaterialSet set = MaterialSet::open(paths, sink);
    build_model(set, o, output, sink);
  }
  sink.rethrow();
  return Model::open(output);
}

py::dict projection_dict(const Model& m, const Projection& p) {
  return py::dict("x"_a = p.x, "relative_error"_a = p.relative_error, "residual2"_a = p.residual2,
                  "variance"_a = p.variance, "nearest"_a = m.names()[static_cast<std::size_t>(p.nearest)],
                  "nearest_index"_a = p.nearest, "nearest_relative_error"_a = p.nearest_relative_error,
                  "missing"_a = p.missing);
}

BrdfTable table_argument(const py::object& table, bool physical) {
  if (py::isinstance<py::str>(table) || py::hasattr(table, "__fspath__")) return read_brdf(table.cast<fs::path>());
  return array_to_table(table.cast<Array>(), physical);
}

}  // namespace
}  // namespace matlas

PYBIND11_MODULE(_matlas, m) {
  using namespace matlas;
  m.doc() = "matlas: Gaussian-process manifolds of measured BRDFs (the C++ core; see the matlas package)";
  py::register_exception<Error>(m, "Error", PyExc_RuntimeError);

  py::class_<Model>(m, "Model", R"doc(A built material map (.matlas file), opened read-only (memory-mapped).

Model(path) opens and validates the file; matlas.Error names the file if it is missing,
truncated, corrupted or not a model.)doc")
      .def(py::init([](const fs::path& path) { return Model::open(path); }), "path"_a)
      .def_property_readonly("path", [](const Model& s) { return s.path(); }, "The model file.")
      .def_property_readonly("names", &Model::names, "Material names, in input order.")
      .def_property_readonly("latent", &Model::latent, "Latent points, an (n, q) array (row i: material i).")
      .def_property_readonly("q", &Model::dim, "Latent dimension q.")
      .def_property_readonly("n", &Model::count, "Number of input materials n.")
      .def_property_readonly("dims", [](const Model& s) { return py::make_tuple(s.dims().theta_h, s.dims().theta_d, s.dims().phi_d); },
                             "Grid (theta_h, theta_d, phi_d) of the tables.")
      .def_property_readonly("kept_columns", &Model::kept_columns,
                             "Values (channel, bin) measured in every input; the others are NaN in tables.")
      .def_property_readonly("storage", &Model::storage, "Precision of the stored data: 'F32' or 'F16'.")
      .def_property_readonly("metadata_json", [](const Model& s) { return s.metadata().dump(); },
                             "The header's metadata as JSON text (Model.metadata parses it).")
      .def("index_of", &Model::index_of, "name"_a, "Index of a material by name (matlas.Error if unknown).")
      .def("weights", [](const Model& s, const Eigen::VectorXd& x) { return intact(s, s.weights(point(s, x))); }, "x"_a,
           "Interpolation weights w(x) = K^-1 k(x), length n; exactly e_i at material i's latent point.")
      .def("weights_batch",
           [](const Model& s, const Eigen::MatrixXd& X) {
             check_points(s, X);
             Eigen::MatrixXd W(X.rows(), s.count());
             py::gil_scoped_release release;
             for (Eigen::Index r = 0; r < X.rows(); ++r) W.row(r) = s.weights(X.row(r).transpose()).transpose();
             return intact(s, std::move(W));
           },
           "X"_a, "weights() of every row of an (m, q) array: an (m, n) array.")
      .def("variance", [](const Model& s, const Eigen::VectorXd& x) { return intact(s, s.variance(point(s, x))); }, "x"_a,
           "GP predictive variance at x in kernel units: 0 at the data, towards 1 far from it.")
      .def("variance_batch",
           [](const Model& s, const Eigen::MatrixXd& X) {
             check_points(s, X);
             Eigen::VectorXd v(X.rows());
             py::gil_scoped_release release;
             for (Eigen::Index r = 0; r < X.rows(); ++r) v[r] = s.variance(X.row(r).transpose());
             return intact(s, std::move(v));
           },
           "X"_a, "variance() of every row of an (m, q) array: an (m,) array.")
      .def("table",
           [](const Model& s, const Eigen::VectorXd& x, bool physical) {
             const Eigen::VectorXd w = s.weights(point(s, x));
             BrdfTable t;
             {
               py::gil_scoped_release release;
               t = s.table(w);
             }
             return intact(s, table_to_array(std::move(t), physical));
           },
           "x"_a, "physical"_a = true,
           "The BRDF table m(x), a (3, theta_h, theta_d, phi_d) float64 array owning its memory (no copy): "
           "physical values with NaN at dropped columns, or MERL stored units with -1 (physical=False).")
      .def("table_batch",
           [](const Model& s, const Eigen::MatrixXd& X, bool physical) {
             check_points(s, X);
             const MerlDims d = s.dims();
             const std::size_t size = 3 * d.bins();
             py::array_t<double> out({static_cast<py::ssize_t>(X.rows()), py::ssize_t{3}, py::ssize_t{d.theta_h},
                                      py::ssize_t{d.theta_d}, py::ssize_t{d.phi_d}});
             double* dst = out.mutable_data();
             py::gil_scoped_release release;
             for (Eigen::Index r = 0; r < X.rows(); ++r) {
               const BrdfTable t = s.table(s.weights(X.row(r).transpose()));
               double* o = dst + static_cast<std::size_t>(r) * size;
               for (int c = 0; c < 3; ++c) {
                 const double scale = physical ? BrdfTable::kChannelScale[static_cast<std::size_t>(c)] : 1.0;
                 const double* in = t.stored().data() + static_cast<std::size_t>(c) * d.bins();
                 double* oc = o + static_cast<std::size_t>(c) * d.bins();
                 for (std::size_t b = 0; b < d.bins(); ++b)
                   oc[b] = physical ? (in[b] < 0.0 ? std::nan("") : in[b] * scale) : in[b];
               }
             }
             return intact(s, std::move(out));
           },
           "X"_a, "physical"_a = true, "table() of every row of an (m, q) array: an (m, 3, theta_h, theta_d, phi_d) array.")
      .def("material_table",
           [](const Model& s, const py::object& which, bool physical) {
             const int i = py::isinstance<py::str>(which) ? s.index_of(which.cast<std::string>()) : which.cast<int>();
             if (i < 0 || i >= s.count()) throw py::index_error("material index out of range");
             BrdfTable t;
             {
               py::gil_scoped_release release;
               t = s.table(s.material_weights(i));
             }
             return intact(s, table_to_array(std::move(t), physical));
           },
           "material"_a, "physical"_a = true, "The stored table of one input material (by name or index).")
      .def("albedo_curve",
           [](const Model& s, const Eigen::VectorXd& x) {
             const std::vector<Rgb> curve = s.albedo_curve(s.weights(point(s, x)));
             Eigen::MatrixXd out(static_cast<Eigen::Index>(curve.size()), 3);
             for (std::size_t k = 0; k < curve.size(); ++k) out.row(static_cast<Eigen::Index>(k)) = curve[k].transpose();
             return intact(s, std::move(out));
           },
           "x"_a, "Directional albedo at 90 view angles (bin centres of [0, 90) degrees): a (90, 3) array.")
      .def("project",
           [](const Model& s, const py::object& table, bool physical, int starts) {
             const BrdfTable t = table_argument(table, physical);
             Projection p;
             {
               py::gil_scoped_release release;
               p = project_material(s, t, starts);
             }
             return intact(s, projection_dict(s, p));
           },
           "table"_a, "physical"_a = true, "starts"_a = 5,
           "Where a material falls on the map: the latent x whose m(x) is closest in L2 over the kept columns.\n"
           "`table` is an array like table() returns, or the path of a MERL .binary or RGL .bsdf file. Returns a dict\n"
           "with x, relative_error, residual2, variance, nearest (name), nearest_index, nearest_relative_error, missing.")
      .def("_table_seconds",
           [](const Model& s, const Eigen::VectorXd& x, int repeats) {
             const Eigen::VectorXd w = s.weights(point(s, x));
             py::gil_scoped_release release;
             const auto t0 = std::chrono::steady_clock::now();
             for (int r = 0; r < repeats; ++r) {
               const Eigen::VectorXd wr = s.weights(x);
               BrdfTable t = s.table(wr);
               (void)t;
             }
             return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / repeats;
           },
           "x"_a, "repeats"_a = 5, "Benchmark helper: seconds per weights() + table() call timed inside C++.");

  // The defaults are the library's (BuildOptions), as `matlas build` uses them.
  const BuildOptions defaults;
  m.def("build", &build, "inputs"_a, "output"_a = py::none(), py::kw_only(), "dim"_a = defaults.dim,
        "nugget"_a = defaults.nugget, "optimizer"_a = gp::to_string(defaults.optimize.method),
        "layout"_a = defaults.layout.to_string(), "storage"_a = "f32", "starts"_a = 0,
        "max_iterations"_a = defaults.optimize.max_iterations, "coarse"_a = defaults.optimize.coarse,
        "sparse_inducing"_a = defaults.sparse.inducing, "progress"_a = py::none(),
        "Builds a map from a folder (every MERL .binary and RGL .bsdf file in it) or a list of files and/or\n"
        "folders, writes it atomically to `output` (or, when None, to a temporary file removed once the model\n"
        "is open) and returns the opened Model. The options are `matlas build`'s (coarse: --coarse,\n"
        "sparse_inducing: --sparse-inducing; max_iterations=-1 and coarse=-1, the defaults, are automatic:\n"
        "from 500 materials on, coarse-to-fine and a refinement whose length falls as n^3). progress(label, done, total)\n"
        "is called as the work advances (any thread, with the GIL held); an exception it raises stops the\n"
        "reporting and is raised again when the build returns.");
  m.def("blas_kernels", [] { return std::string(blas::openblas().corename()); },
        "The OpenBLAS kernels that builds and queries run on (\"SkylakeX\", \"Haswell\", \"Prescott\", ...).\n"
        "numpy usually loads OpenBLAS first, before matlas can choose: set OPENBLAS_CORETYPE before\n"
        "starting Python if this names older kernels than the processor has (docs/PYTHON.md).");
  m.def("read_merl",
        [](const fs::path& path, bool physical) {
          BrdfTable t;
          {
            py::gil_scoped_release release;
            t = read_brdf(path);
          }
          return table_to_array(std::move(t), physical);
        },
        "path"_a, "physical"_a = true,
        "Reads a MERL .binary file (or an RGL .bsdf file, resampled onto the MERL grid) as a (3, theta_h,\n"
        "theta_d, phi_d) float64 array: physical values with NaN where missing, or stored units (physical=False).");
  m.def("write_merl",
        [](const fs::path& path, const Array& table, bool physical, bool allow_nonstandard_dims) {
          const BrdfTable t = array_to_table(table, physical);
          py::gil_scoped_release release;
          write_merl(path, t, allow_nonstandard_dims);
        },
        "path"_a, "table"_a, "physical"_a = true, "allow_nonstandard_dims"_a = false,
        "Writes a table as a MERL .binary file, atomically. NaN (or a negative value) is written as missing (-1).\n"
        "Grids other than 90x90x180 are refused unless allow_nonstandard_dims.");
  m.def("brdf_distance",
        [](const py::object& a, const py::object& b, bool physical) {
          const BrdfTable ta = table_argument(a, physical), tb = table_argument(b, physical);
          const eval::BrdfDistance d = eval::brdf_distance(ta, tb);
          return py::dict("cbrt_cosine"_a = d.cbrt_cosine, "cosine_rmse"_a = d.cosine_rmse, "values"_a = d.values);
        },
        "a"_a, "b"_a, "physical"_a = true,
        "The evaluation's distances between two tables (arrays or file paths): the cosine-weighted cube-root\n"
        "distance (Fores et al. 2012) and the cosine-weighted RMSE, over values measured in both, as a dict\n"
        "{cbrt_cosine, cosine_rmse, values}.");

  bind_acquisition(m);

  py::class_<RglBsdf>(m, "RglBsdf", "An RGL measured material (.bsdf file), evaluated as the reference implementation does.")
      .def(py::init([](const fs::path& path) { return RglBsdf::read(path); }), "path"_a)
      .def_property_readonly("description", &RglBsdf::description)
      .def_property_readonly("isotropic", &RglBsdf::isotropic)
      .def_property_readonly("summary", &RglBsdf::summary)
      .def("eval",
           [](const RglBsdf& b, const Eigen::MatrixXd& wi, const Eigen::MatrixXd& wo, bool cosine) {
             if (wi.cols() != 3 || wo.cols() != 3 || wi.rows() != wo.rows())
               throw py::value_error("wi and wo are (m, 3) arrays of unit vectors with the same m");
             Eigen::MatrixXd out(wi.rows(), 3);
             for (Eigen::Index r = 0; r < wi.rows(); ++r) {
               const Vec3 a = wi.row(r).transpose(), c = wo.row(r).transpose();
               out.row(r) = (cosine ? b.eval_cosine(a, c) : b.eval(a, c)).transpose();
             }
             return out;
           },
           "wi"_a, "wo"_a, "cosine"_a = false,
           "RGB f(wi, wo) for rows of (m, 3) arrays of unit directions (normal +z; wi the light): the BRDF,\n"
           "or f cos(theta_o) as Mitsuba returns it (cosine=True). 0 below the horizon.")
      .def("resample",
           [](const RglBsdf& b, bool physical) {
             BrdfTable t;
             {
               py::gil_scoped_release release;
               t = resample_to_merl(b);
             }
             return table_to_array(std::move(t), physical);
           },
           "physical"_a = true, "The table resampled onto the MERL grid (as `matlas import` writes it).");
}
