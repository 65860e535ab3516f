#include "atlas/gi_density.h"

#include <nlohmann/json.hpp>

#include "atlas/sampling_fit.h"
#include "core/hash.h"

namespace matlas::atlas {

namespace {

SamplingFitOptions gi_fit_options() {
  SamplingFitOptions o;
  o.environment = 0.0;
  o.cosine = 0.1;
  o.lobe_share = 0.1;
  o.sharpest_share = 0.3;
  o.tabulated = 0.3;
  return o;
}

}  // namespace

pathtrace::FixedDensity fit_gi_density(const Model& model) { return fit_sampling_mixture(model, gi_fit_options()); }

pathtrace::FixedDensity fit_gi_density(const render::MaterialBank& bank) {
  return fit_sampling_mixture(bank, gi_fit_options());
}

std::string density_record(const pathtrace::FixedDensity& d) {
  nlohmann::json lobes = nlohmann::json::array();
  for (const auto& [alpha, weight] : d.lobes) lobes.push_back({alpha, weight});
  const std::vector<double>& profile = d.profile();
  Xxh3Hasher h;
  h.update(profile.data(), profile.size() * sizeof(double));
  return nlohmann::json{{"cosine", d.cosine}, {"lobes", lobes}, {"tabulated", d.tabulated},
                        {"profile_hash", hex64(h.digest())}}
      .dump();
}

}  // namespace matlas::atlas
