#pragma once
// The fit of an analytic model to a tabulated BRDF: the parameters an artist's tool needs to show
// a material close to the table. Two models: the glTF metallic-roughness model (brdf/gltf_pbr.h;
// glTF viewers, Blender 4, Standard Surface, OpenPBR) and Blender 2.8-3.6's Principled BSDF
// (brdf/principled_v1.h), by the same search on the same coordinates.
//
// Objective: Fores et al.'s cosine-weighted cube-root difference (eval/brdf_distance.h, the
// evaluation's perceptual metric), (cbrt(c f_model) - cbrt(c f_table))^2 with c = cos(theta_i)
// cos(theta_o) at the bin centre, integrated over pairs of directions (each bin weighted by its
// solid angle in (wi, wo)) instead of averaged over bins: MERL's bins crowd near the mirror
// direction, and the plain mean lets grazing near-specular pairs, where measured Fresnel rises
// far beyond any Schlick term, outweigh the highlight (on gray-plastic it preferred no specular
// lobe at all). On every theta_h bin and a regular subsample of theta_d and phi_d.
// Minimised by Nelder-Mead (gp/minimize.h) on the eight parameters (base colour, metallic,
// roughness, specular, clearcoat and its roughness; roughnesses by their logarithm), from eight starts
// matched to the table's back-scattering peak (its width gives a roughness, its height the specular
// factor or the metal's F0; metal and dielectric at three roughnesses, and under a coat) on a coarser
// subsample, then polished from the best on the full subsample and restarted once to check
// convergence. Then a sheen stage (fabrics: a neutral KHR_materials_sheen layer, its strength and
// roughness, with the eight others free again) from four starts, kept only if it lowers the
// distance by more than 2 %. Principled v1: "Specular" in place of the specular factor (starts at
// half of it: F0 = 0.08 x "Specular"), "Sheen" and "Sheen Tint" in the sheen stage, "Specular
// Tint" left at 0. Deterministic.
#include <cstddef>

#include "brdf/brdf_table.h"
#include "brdf/gltf_pbr.h"
#include "brdf/principled_v1.h"

namespace matlas::artist {

struct PbrFitOptions {
  int theta_d_stride = 6;            ///< every k-th theta_d bin enters the objective
  int phi_d_stride = 15;             ///< every k-th phi_d bin
  int evaluations_per_start = 800;   ///< Nelder-Mead budget of each start (on a 4x coarser subsample)
  int polish_evaluations = 1200;     ///< budget of the final polish from the best start
  int restart_evaluations = 200;     ///< budget of the restart that checks convergence
  double ior = 1.5;                  ///< glTF: fixed (KHR_materials_ior); the specular factor is fitted
  /// The sheen stage (KHR_materials_sheen, a neutral sheen colour and its roughness), kept when it
  /// lowers the distance by more than `sheen_gain` (relative).
  bool sheen = true;
  double sheen_gain = 0.02;
};

template <class Fitted>
struct AnalyticFit {
  Fitted model;
  /// sqrt of the objective at the result: the measure-weighted cube-root distance on the samples.
  double distance = 0;
  std::size_t samples = 0;  ///< bins in the objective
  int starts = 0;
  int evaluations = 0;      ///< objective evaluations, all starts and the polish
  /// Decrease of `distance` by a restart of Nelder-Mead from the result (the classic check of
  /// its convergence). Converged when at most 1e-3 of the distance (plus 1e-6): otherwise the
  /// search stopped on its budget and the parameters may still be off.
  double restart_gain = 0;
  bool converged() const { return restart_gain <= 1e-3 * distance + 1e-6; }
};

using PbrFitResult = AnalyticFit<GltfPbr>;
using PrincipledV1FitResult = AnalyticFit<PrincipledV1>;

/// Fits the model to `table` (values missing in any channel, -1, and bins below the horizon are
/// left out). Throws matlas::Error if the table has no usable value.
PbrFitResult fit_gltf_pbr(const BrdfTable& table, const PbrFitOptions& options = {});
PrincipledV1FitResult fit_principled_v1(const BrdfTable& table, const PbrFitOptions& options = {});

}  // namespace matlas::artist
