#pragma once
// Firefly removal for the images shown while the user drags (the scene view's composed GI image,
// docs/GI.md): a path-traced basis of few samples per pixel has isolated pixels where one rare
// path (a caustic through a glossy floor) carried a large weight, tens of times brighter than the
// pixel's true value. Such a pixel is replaced by the median of its 8 neighbours when its
// luminance exceeds `ratio` times the second brightest of theirs (rank 2; rank 1: the brightest),
// so that two or three bright pixels together among dim ones go too (a caustic path often lights
// more than one). A real highlight falls off over its neighbours and is kept, as are the inner
// pixels of a bright line; a thin line's end pixels, with one bright neighbour, are taken when
// they stand out from the rest. BIASED (it removes energy, and a true glint of a pixel or two
// with it): never applied to an image that is refined, exported or composed further; the
// refinement at rest (unbiased) replaces the filtered image.
#include "formats/image_io.h"

namespace matlas::render {

/// The ratio and rank of the scene view's drag image: on the floor scene's 16-spp composition
/// they take the 19 pixels that exceeded 20x a 256-spp reference to none (and 2 where the
/// reference is dark to 1), and lower its relative L1 error from 0.280 to 0.221 (docs/GI.md).
inline constexpr double kFireflyRatio = 2.5;
inline constexpr int kFireflyRank = 2;

/// Filters `image` in place; returns the number of pixels replaced. `rank` 2 compares a pixel with
/// the second brightest of its neighbours (on the image's border, with fewer than 8, the
/// brightest), 1 with the brightest. Throws matlas::Error for a ratio below 1 or another rank.
int remove_fireflies(Image& image, double ratio = kFireflyRatio, int rank = kFireflyRank);

}  // namespace matlas::render
