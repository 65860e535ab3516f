#pragma once
// The measured object's sampling density in a model's GI images, fitted to the model's database
// (docs/GI.md "Fireflies"). It is the same for every material of the model, so the images stay
// linear in the table (I = P + N z + I2) and a direct render of a map point with the same density
// and random numbers equals the composition of the basis.
//
// Why fitted: measured peaks are far sharper than any fixed lobe (chrome's first theta_h bins
// hold values of 3,000-4,000 per sr; the former fixed density's sharpest lobe, GGX alpha 0.02,
// reaches a density of about 60 at the mirror direction), so f cos / pdf of a path vertex on the
// object reached hundreds: the object's lower half (object -> glossy floor -> the studio's small
// lights) and its rim were fireflies. The fitted density (atlas/sampling_fit.h) adds the
// database's lobes per MERL theta_h bin (constant over each bin, like the tables) and a GGX lobe
// at the sharpest material's width, so f / pdf stays bounded for every material of the database.
#include <string>

#include "pathtrace/surface.h"

namespace matlas {
class Model;
}
namespace matlas::render {
class MaterialBank;
}

namespace matlas::atlas {

/// The density fitted to `model`'s database materials: no environment strategy (next-event
/// estimation takes the environment), cosine 0.1, the three quantile GGX lobes 0.1 each, a GGX
/// lobe at the sharpest material's width 0.3 and the tabulated theta_h lobe 0.3.
pathtrace::FixedDensity fit_gi_density(const Model& model);
/// The same fit to a bank's materials (a MERL file traced on its own: its lobes' widths).
pathtrace::FixedDensity fit_gi_density(const render::MaterialBank& bank);

/// A record of a density (probabilities, lobes and a hash of the tabulated profile), as basis
/// keys and file metadata hold it.
std::string density_record(const pathtrace::FixedDensity& density);

}  // namespace matlas::atlas
