#pragma once
// Image bases of a model (render/image_basis.h): the images of its mean and of every database
// material, from which any point of the map is composed.
#include <string>

#include "core/progress.h"
#include "manifold/model.h"
#include "render/image_basis.h"

namespace matlas::render {
class Scene;
struct RenderSettings;
}  // namespace matlas::render

namespace matlas::atlas {

/// Renders the basis of a model: the mean (w = 0) and every material i (w = e_i, i.e.
/// Model::material_weights(i)) with identical samples, through the sampling mixture fitted to the
/// model (atlas/sampling_fit.h; the settings' own mixture is replaced). Metadata: names, spp,
/// seed, width, height, scene fields, sampling_mixture (sampling_record), model name and fingerprint.
render::ImageBasis render_basis(const Model& model, const render::Scene& scene, const render::RenderSettings& settings,
                                ProgressSink& progress = null_progress());

/// The sampling of a render as JSON text: the sampler, the mixture's probabilities and lobes,
/// and a hash of the tabulated lobe's profile. A basis records it (metadata "sampling_mixture"),
/// and a cached basis is reused only when it equals the record of the settings at hand, so a
/// basis from another sampler or mixture is never combined with direct renders.
std::string sampling_record(const render::RenderSettings& settings);

/// A short stable fingerprint of a model (hex of a 64-bit hash of its metadata and latent
/// points), stored in bases to check they belong to a model.
std::string model_fingerprint(const Model& model);

}  // namespace matlas::atlas
