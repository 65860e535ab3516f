#pragma once
// The zonal coefficients of a model, cached beside it (issue 12): MODEL.zonal-L<bands>, a
// coefficient file (zonal/coefficient_file.h, float32) whose metadata "source_key" identifies
// what it was computed from: the model's content (its header metadata, which holds the xxh3
// digests of every input's values and the checksum of the small tensors; its grid, kept columns
// and storage) and the projection settings. A cache whose key, settings or names differ (a
// rebuilt model), or that cannot be read (truncated, corrupted), is recomputed and rewritten
// atomically; a cache that cannot be written (read-only folder) leaves the computed set in use.
#include <filesystem>
#include <string>

#include "manifold/model.h"
#include "zonal/coefficient_file.h"

namespace matlas::atlas {

/// MODEL.zonal-L<bands> beside the model file.
std::filesystem::path zonal_cache_path(const std::filesystem::path& model_path, int bands);

/// 16 hex digits of xxh3 over the model's content description and the settings.
std::string zonal_cache_key(const Model& model, const zonal::ProjectionSettings& settings);

struct CachedCoefficients {
  zonal::CoefficientSet set;
  bool loaded = false;  ///< read from the cache (else computed)
  double seconds = 0;   ///< wall time of the load or of the computation (and write)
  std::string note;     ///< what happened: "loaded", or why it was computed, and whether it was written
};

/// The model's coefficients (atlas::model_coefficients) through the cache at `cache`.
CachedCoefficients cached_model_coefficients(const Model& model, const zonal::ProjectionSettings& settings,
                                             const std::filesystem::path& cache);

}  // namespace matlas::atlas
