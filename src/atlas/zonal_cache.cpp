#include "atlas/zonal_cache.h"

#include <chrono>
#include <system_error>

#include <nlohmann/json.hpp>

#include "atlas/model_zonal.h"
#include "core/error.h"
#include "core/hash.h"

namespace matlas::atlas {

std::filesystem::path zonal_cache_path(const std::filesystem::path& model_path, int bands) {
  std::filesystem::path p = model_path;
  p += ".zonal-L" + std::to_string(bands);
  return p;
}

std::string zonal_cache_key(const Model& model, const zonal::ProjectionSettings& settings) {
  nlohmann::json key = {
      {"cache", "matlas-zonal-cache 1"},
      {"model_metadata", model.metadata()},
      {"dims", model.dims().to_string()},
      {"kept_columns", model.kept_columns()},
      {"storage", model.storage()},
      {"bands", settings.bands},
      {"theta_o_count", settings.theta_o_count},
      {"theta_rows", settings.theta_rows},
      {"phi_columns", settings.phi_columns},
  };
  if (!settings.lobes.empty()) {  // keys of sets without lobes unchanged
    key["lobes"] = settings.lobes;
    key["lobe_fit"] = "nonnegative";  // zonal/lobes.h: caches of the former unconstrained fit are stale
  }
  if (settings.ring_floor >= 0.0) key["ring_floor"] = settings.ring_floor;  // likewise
  return hex64(xxh3_64(key.dump()));
}

namespace {

bool same_settings(const zonal::ProjectionSettings& a, const zonal::ProjectionSettings& b) {
  return a.bands == b.bands && a.theta_o_count == b.theta_o_count && a.theta_rows == b.theta_rows &&
         a.phi_columns == b.phi_columns && a.lobes == b.lobes && a.ring_floor == b.ring_floor;
}

}  // namespace

CachedCoefficients cached_model_coefficients(const Model& model, const zonal::ProjectionSettings& settings,
                                             const std::filesystem::path& cache) {
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const std::string key = zonal_cache_key(model, settings);
  CachedCoefficients out;
  std::error_code ec;
  if (!std::filesystem::exists(cache, ec)) {
    out.note = "no cache at " + cache.string();
  } else {
    try {
      zonal::CoefficientSet set = zonal::read_coefficients(cache);
      if (set.source_key != key || !same_settings(set.settings, settings) || set.names != model.names() || !set.mean) {
        out.note = cache.string() + " is stale (computed from another model or with other settings)";
      } else {
        out.set = std::move(set);
        out.loaded = true;
        out.note = "loaded " + cache.string();
        out.seconds = elapsed();
        return out;
      }
    } catch (const Error& e) {
      out.note = std::string("refused the cache: ") + e.what();
    }
  }
  out.set = model_coefficients(model, settings);
  out.set.source_key = key;
  try {
    zonal::write_coefficients(cache, out.set, DType::F32);
    out.note += "; computed and written to " + cache.string();
  } catch (const Error& e) {
    out.note += std::string("; computed, not cached: ") + e.what();
  }
  out.seconds = elapsed();
  return out;
}

}  // namespace matlas::atlas
