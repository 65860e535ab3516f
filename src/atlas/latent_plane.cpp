#include "atlas/latent_plane.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>

#include "core/check.h"
#include "core/error.h"
#include "core/huge_pages.h"

namespace matlas::atlas {

namespace {

void extent(const Model& model, LatentPlane& plane, double margin, const std::vector<bool>* keep = nullptr) {
  double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
  for (int i = 0; i < model.count(); ++i) {
    if (keep && !(*keep)[static_cast<std::size_t>(i)]) continue;
    const Eigen::Vector2d p = plane.project(model.latent().row(i).transpose());
    u0 = std::min(u0, p.x()), u1 = std::max(u1, p.x()), v0 = std::min(v0, p.y()), v1 = std::max(v1, p.y());
  }
  // The data's box plus the margin (a fraction of its longer side) on every side; the shorter
  // side is widened about its centre only as far as needed to keep the aspect within 1:3.
  const double longer = std::max({u1 - u0, v1 - v0, 1e-6});
  const double pad = margin * longer;
  double du = (u1 - u0) + 2 * pad, dv = (v1 - v0) + 2 * pad;
  const double longest = std::max(du, dv);
  du = std::max(du, longest / 3), dv = std::max(dv, longest / 3);
  const double cu = 0.5 * (u0 + u1), cv = 0.5 * (v0 + v1);
  plane.u_min = cu - 0.5 * du, plane.u_max = cu + 0.5 * du;
  plane.v_min = cv - 0.5 * dv, plane.v_max = cv + 0.5 * dv;
}

void check_at(const Model& model, const Eigen::VectorXd& at) {
  if (at.size() != model.dim())
    throw Error("latent map: the fixed point has " + std::to_string(at.size()) + " coordinates, the model q = " +
                std::to_string(model.dim()));
}

}  // namespace

LatentPlane LatentPlane::rectangle(const Eigen::VectorXd& at, int d0, int d1, double u0, double u1, double v0,
                                   double v1) {
  const auto q = static_cast<int>(at.size());
  if (d0 < 0 || d0 >= q || d1 < 0 || d1 >= q || d0 == d1)
    throw Error("latent map: the axes must be two different dimensions in 0.." + std::to_string(q - 1));
  if (!(u0 < u1 && v0 < v1)) throw Error("latent map: the rectangle must have u0 < u1 and v0 < v1");
  LatentPlane p;
  p.origin = at;
  p.origin[d0] = 0, p.origin[d1] = 0;
  p.axis_u = Eigen::VectorXd::Unit(q, d0);
  p.axis_v = Eigen::VectorXd::Unit(q, d1);
  p.u_min = u0, p.u_max = u1, p.v_min = v0, p.v_max = v1;
  return p;
}

LatentPlane LatentPlane::from_dims(const Model& model, int d0, int d1, const Eigen::VectorXd& at, double margin) {
  const int q = model.dim();
  if (d0 < 0 || d0 >= q || d1 < 0 || d1 >= q || d0 == d1)
    throw Error("latent map: --dims must be two different dimensions in 0.." + std::to_string(q - 1));
  check_at(model, at);
  LatentPlane p = rectangle(at, d0, d1, -1, 1, -1, 1);
  extent(model, p, margin);
  return p;
}

LatentPlane LatentPlane::pca(const Model& model, const Eigen::VectorXd& at, double margin) {
  const int q = model.dim();
  check_at(model, at);
  if (q < 2) return automatic(model, margin);
  const Eigen::MatrixXd centred = model.latent().rowwise() - model.latent().colwise().mean();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(centred.transpose() * centred);
  LatentPlane p;
  p.axis_u = eig.eigenvectors().col(q - 1);
  p.axis_v = eig.eigenvectors().col(q - 2);
  // Origin: `at` with its components along the plane removed (u, v = 0 is the projection of 0).
  p.origin = at - at.dot(p.axis_u) * p.axis_u - at.dot(p.axis_v) * p.axis_v;
  extent(model, p, margin);
  return p;
}

LatentPlane LatentPlane::automatic(const Model& model, double margin) {
  const Eigen::VectorXd mean = model.latent().colwise().mean().transpose();
  if (model.dim() >= 2) return from_dims(model, 0, 1, mean, margin);
  LatentPlane p;
  p.origin = Eigen::VectorXd::Zero(1);
  p.axis_u = Eigen::VectorXd::Unit(1, 0);
  p.axis_v = Eigen::VectorXd::Zero(1);
  extent(model, p, margin);
  return p;
}

int frame_core(const Model& model, LatentPlane& plane, double margin) {
  const int n = model.count();
  std::vector<double> us, vs;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d p = plane.project(model.latent().row(i).transpose());
    us.push_back(p.x()), vs.push_back(p.y());
  }
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  const double mu = median(us), mv = median(vs);
  std::vector<double> d(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = std::hypot(us[i] - mu, vs[i] - mv);
  const double limit = 4.0 * median(d);  // the median itself keeps at least half
  std::vector<bool> keep(d.size());
  for (std::size_t i = 0; i < d.size(); ++i) keep[i] = d[i] <= limit;
  extent(model, plane, margin, &keep);
  int outside = 0;
  for (std::size_t i = 0; i < d.size(); ++i)
    outside += us[i] < plane.u_min || us[i] > plane.u_max || vs[i] < plane.v_min || vs[i] > plane.v_max;
  return outside;
}

LatentGrid latent_grid(const Model& model, const LatentPlane& plane, int cols, int rows) {
  return latent_grid(model, plane, cols, rows, model.interpolation());
}

LatentGrid latent_grid(const Model& model, const LatentPlane& plane, int cols, int rows, Interpolation mode,
                       double project_below) {
  if (cols <= 0 || rows <= 0) throw Error("latent map: grid size must be positive");
  MATLAS_CHECK(plane.origin.size() == model.dim() && plane.axis_u.size() == model.dim() &&
                   plane.axis_v.size() == model.dim(),
               "a plane in the model's latent space");
  LatentGrid g;
  g.cols = cols, g.rows = rows;
  const Eigen::VectorXd u = plane.cell_u(cols), v = plane.cell_v(rows);
  g.points.resize(static_cast<Eigen::Index>(cols) * rows, model.dim());
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) g.points.row(static_cast<Eigen::Index>(r) * cols + c) = plane.point(u[c], v[r]).transpose();
  // The GP's weights through the kernel's separability on the plane (Model::predict_grid).
  Model::Prediction predicted = model.predict_grid(plane.origin, plane.axis_u, plane.axis_v, u, v);
  g.weights = std::move(predicted.weights);
  g.variance = std::move(predicted.variance);
  if (mode != Interpolation::convex) return g;
  // The cells to project, in serpentine order (odd rows right to left), so that consecutive
  // points are neighbours: each point's convex weights are solved from the previous point's
  // (Model::weights_from_gp_batch).
  std::vector<Eigen::Index> projected;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const Eigen::Index k = static_cast<Eigen::Index>(r) * cols + (r % 2 ? cols - 1 - c : c);
      if (g.variance[k] < project_below) projected.push_back(k);
    }
  if (projected.empty()) return g;
  Eigen::MatrixXd part(g.weights.rows(), static_cast<Eigen::Index>(projected.size()));
  advise_huge_pages(part.data(), static_cast<std::size_t>(part.size()) * sizeof(double));
  part = g.weights(Eigen::all, projected);
  model.weights_from_gp_batch(part, mode);
  g.weights(Eigen::all, projected) = part;
  return g;
}

}  // namespace matlas::atlas
