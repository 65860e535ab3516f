#pragma once
// Image bases of a model (render/image_basis.h): the images of its mean and of every database
// material, from which any point of the map is composed.
#include <string>

#include "core/communicator.h"
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
///
/// Split across processes (`mpirun -np P matlas basis`): every rank renders every P-th row of the
/// n + 1 images (render::RowShare; the pixels are the single process's) and rank 0 gathers them;
/// the other ranks return an empty basis.
render::ImageBasis render_basis(const Model& model, const render::Scene& scene, const render::RenderSettings& settings,
                                ProgressSink& progress = null_progress(), Communicator& comm = serial_communicator());

/// Every rank's images (its share, in order) on rank 0, in rank order; empty elsewhere. The
/// images share one size.
std::vector<Image> gather_images(std::vector<Image> mine, Communicator& comm);

/// The images of `height` rows whose rows the ranks rendered by render::RowShare{rank, size} (every
/// rank the same images, in the same order), assembled on rank 0; empty elsewhere.
std::vector<Image> gather_rows(std::vector<Image> mine, int height, Communicator& comm);

/// The sampling of a render as JSON text: the sampler, the mixture's probabilities and lobes,
/// and a hash of the tabulated lobe's profile. A basis records it (metadata "sampling_mixture"),
/// and a cached basis is reused only when it equals the record of the settings at hand, so a
/// basis from another sampler or mixture is never combined with direct renders.
std::string sampling_record(const render::RenderSettings& settings);

/// A short stable fingerprint of a model (hex of a 64-bit hash of its metadata and latent
/// points), stored in bases to check they belong to a model.
std::string model_fingerprint(const Model& model);

}  // namespace matlas::atlas
