#include "cli/latent_point.h"

#include <cmath>
#include <sstream>
#include <vector>

#include "core/error.h"

namespace matlas::cli {

Eigen::VectorXd parse_point(const std::string& text) {
  std::vector<double> values;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    while (used < item.size() && std::isspace(static_cast<unsigned char>(item[used]))) ++used;
    if (item.empty() || used != item.size())
      throw Error("--at: '" + item + "' is not a number (expected x1,...,xq)");
    if (!std::isfinite(v)) throw Error("--at: coordinate '" + item + "' is not finite");
    values.push_back(v);
  }
  if (values.empty()) throw Error("--at: no coordinates given (expected x1,...,xq)");
  return Eigen::Map<Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

Eigen::VectorXd resolve_point(const Model& model, const std::optional<std::string>& at,
                              const std::optional<std::string>& material) {
  if (material) return model.latent().row(model.index_of(*material)).transpose();
  if (!at) throw Error("give a latent point with --at x1,...,xq or --material NAME");
  Eigen::VectorXd x = parse_point(*at);
  if (x.size() != model.dim())
    throw Error("--at has " + std::to_string(x.size()) + " coordinates but the model has q = " +
                std::to_string(model.dim()));
  return x;
}

void add_point_options(CLI::App& cmd, std::optional<std::string>& at,
                       std::optional<std::string>& material) {
  auto* a = cmd.add_option("--at", at, "Latent point x1,...,xq");
  auto* m = cmd.add_option("--material", material, "A database material's own latent point");
  a->excludes(m);
}

}  // namespace matlas::cli
