// The glTF metallic-roughness fit: parameters recovered from tables of the model itself, sensible
// fits of tables made by other models, and the error measures against closed forms.
#include <cmath>

#include <gtest/gtest.h>

#include "artist/fit_error.h"
#include "artist/pbr_fit.h"
#include "brdf/analytic.h"
#include "brdf/gltf_pbr.h"
#include "brdf/principled_v1.h"
#include "brdf/tabulate.h"

namespace matlas {
namespace {

void expect_recovered(const GltfPbr& truth, const artist::PbrFitResult& fit) {
  const GltfPbr& m = fit.model;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(m.base_color[c], truth.base_color[c], 0.02) << "channel " << c;
  EXPECT_NEAR(m.metallic, truth.metallic, 0.02);
  EXPECT_NEAR(m.roughness, truth.roughness, 0.01);
  EXPECT_NEAR(m.specular, truth.specular, 0.03);
  EXPECT_LT(fit.distance, 1e-3);
  EXPECT_TRUE(fit.converged()) << fit.restart_gain;
}

TEST(PbrFit, RecoversTheParametersOfARoughDielectric) {
  const GltfPbr truth{Rgb(0.6, 0.12, 0.05), 0.0, 0.35, 1.0, 1.5};
  const BrdfTable table = tabulate(truth);
  const artist::PbrFitResult fit = artist::fit_gltf_pbr(table);
  expect_recovered(truth, fit);
  EXPECT_LT(artist::fit_error(table, fit.model).relative_rms, 0.01);
}

TEST(PbrFit, RecoversTheParametersOfAGlossyMetal) {
  const GltfPbr truth{Rgb(0.95, 0.75, 0.35), 1.0, 0.2, 1.0, 1.5};
  const artist::PbrFitResult fit = artist::fit_gltf_pbr(tabulate(truth));
  // Metallic at 1 leaves the specular factor (a dielectric parameter) undetermined.
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(fit.model.base_color[c], truth.base_color[c], 0.02);
  EXPECT_GT(fit.model.metallic, 0.98);
  EXPECT_NEAR(fit.model.roughness, truth.roughness, 0.01);
  EXPECT_LT(fit.distance, 1e-3);
}

TEST(PbrFit, RecoversASharpWeakCoatingOverADarkBase) {
  const GltfPbr truth{Rgb(0.05, 0.08, 0.2), 0.0, 0.1, 0.6, 1.5};
  expect_recovered(truth, artist::fit_gltf_pbr(tabulate(truth)));
}

TEST(PbrFit, RecoversTheSheenOfAVelvetAndAddsNoneWithoutOne) {
  // A rough red dielectric under a neutral sheen (KHR_materials_sheen): the sheen stage finds it,
  // which the eight parameters alone cannot imitate; the materials above keep no sheen.
  GltfPbr truth{Rgb(0.5, 0.08, 0.06), 0.0, 0.8, 0.5, 1.5};
  truth.sheen_color = Rgb::Constant(0.7);
  truth.sheen_roughness = 0.35;
  const BrdfTable table = tabulate(truth);
  const artist::PbrFitResult fit = artist::fit_gltf_pbr(table);
  EXPECT_NEAR(fit.model.sheen_color[0], 0.7, 0.05);
  EXPECT_NEAR(fit.model.sheen_roughness, 0.35, 0.05);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(fit.model.base_color[c], truth.base_color[c], 0.03) << c;
  EXPECT_LT(fit.model.metallic, 0.05);
  EXPECT_LT(fit.distance, 2e-3);
  artist::PbrFitOptions without;
  without.sheen = false;
  EXPECT_GT(artist::fit_gltf_pbr(table, without).distance, 3.0 * fit.distance);
  const GltfPbr plain{Rgb(0.6, 0.12, 0.05), 0.0, 0.35, 1.0, 1.5};
  EXPECT_EQ(artist::fit_gltf_pbr(tabulate(plain)).model.sheen_color.maxCoeff(), 0.0);
}

TEST(PbrFit, APlasticOfAnotherModelFitsAsADielectricOfItsRoughness) {
  // brdf/analytic.h's plastic: exact dielectric Fresnel and a base seen through the coating twice,
  // not glTF's Schlick mix; the fit finds a dielectric with about the same lobe width and base
  // (0.336 and 83 % of the base on the day this was written: the exact Fresnel dims the base more
  // near grazing) and, what counts, about the same reflectance.
  const RoughPlastic plastic{Rgb(0.1, 0.4, 0.15), 0.09, 1.5, 1.0};
  const BrdfTable table = tabulate(plastic);
  const artist::PbrFitResult fit = artist::fit_gltf_pbr(table);
  EXPECT_LT(fit.model.metallic, 0.1);
  EXPECT_NEAR(fit.model.roughness, 0.3, 0.05);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(fit.model.base_color[c], plastic.diffuse[c], 0.2 * plastic.diffuse[c] + 0.01);
  const artist::FitError e = artist::fit_error(table, fit.model);
  EXPECT_LT(e.relative_rms, 0.1);
  EXPECT_LT(e.albedo_error, 0.15);  // 11 %: glTF's Schlick mix against the exact Fresnel
}

TEST(PbrFit, AConductorOfAnotherModelFitsAsAMetal) {
  const GgxConductor copper{Rgb(0.955, 0.638, 0.538), 0.04};
  const BrdfTable table = tabulate(copper);
  const artist::PbrFitResult fit = artist::fit_gltf_pbr(table);
  EXPECT_GT(fit.model.metallic, 0.9);
  EXPECT_NEAR(fit.model.roughness, 0.2, 0.01);
  EXPECT_LT(artist::fit_error(table, fit.model).relative_rms, 0.05);
}

TEST(PrincipledV1Fit, RecoversTheParametersOfADielectricAndOfACoatedMetal) {
  // Blender 2.8-3.6's Principled BSDF fitted to tables of itself (brdf/principled_v1.h).
  PrincipledV1 plastic;
  plastic.base_color = Rgb(0.6, 0.12, 0.05);
  plastic.specular = 0.5;
  plastic.roughness = 0.35;
  const BrdfTable table = tabulate(plastic);
  const artist::PrincipledV1FitResult fit = artist::fit_principled_v1(table);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(fit.model.base_color[c], plastic.base_color[c], 0.02) << c;
  EXPECT_LT(fit.model.metallic, 0.02);
  EXPECT_NEAR(fit.model.roughness, 0.35, 0.01);
  EXPECT_NEAR(fit.model.specular, 0.5, 0.03);
  EXPECT_LT(fit.model.coat, 0.05);
  EXPECT_LT(fit.distance, 1e-3);
  EXPECT_TRUE(fit.converged()) << fit.restart_gain;
  EXPECT_LT(artist::fit_error(table, fit.model).relative_rms, 0.01);

  PrincipledV1 paint;
  paint.base_color = Rgb(0.3, 0.2, 0.1);
  paint.metallic = 1.0;
  paint.roughness = 0.4;
  paint.coat = 0.8;
  paint.coat_roughness = 0.1;
  const artist::PrincipledV1FitResult coated = artist::fit_principled_v1(tabulate(paint));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(coated.model.base_color[c], paint.base_color[c], 0.02) << c;
  EXPECT_GT(coated.model.metallic, 0.95);
  EXPECT_NEAR(coated.model.roughness, 0.4, 0.02);
  EXPECT_NEAR(coated.model.coat, 0.8, 0.05);
  EXPECT_NEAR(coated.model.coat_roughness, 0.1, 0.01);
  EXPECT_LT(coated.distance, 2e-3);
}

TEST(PrincipledV1Fit, RecoversADisneySheenAndAddsNoneWithoutOne) {
  PrincipledV1 velvet;
  velvet.base_color = Rgb(0.5, 0.08, 0.06);
  velvet.roughness = 0.8;
  velvet.sheen = 0.8;
  velvet.sheen_tint = 0.3;
  const artist::PrincipledV1FitResult fit = artist::fit_principled_v1(tabulate(velvet));
  EXPECT_NEAR(fit.model.sheen, 0.8, 0.05);
  EXPECT_NEAR(fit.model.sheen_tint, 0.3, 0.05);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(fit.model.base_color[c], velvet.base_color[c], 0.02) << c;
  EXPECT_LT(fit.distance, 2e-3);
  PrincipledV1 plain = velvet;
  plain.sheen = 0.0;
  EXPECT_EQ(artist::fit_principled_v1(tabulate(plain)).model.sheen, 0.0);
}

TEST(FitError, IsZeroForTheModelItselfAndTheRelativeOffsetOfAScaledOne) {
  const GltfPbr lambert{Rgb(0.5, 0.3, 0.2), 0.0, 0.5, 0.0, 1.5};
  const BrdfTable table = tabulate(lambert);
  const artist::FitError same = artist::fit_error(table, lambert);
  EXPECT_LT(same.relative_rms, 1e-6);
  EXPECT_LT(same.cbrt_distance, 1e-6);
  EXPECT_LT(same.albedo_error, 2e-3);  // the table's smooth lookup against the function
  // 10 % brighter everywhere: relative RMS and albedo difference 10 %.
  GltfPbr brighter = lambert;
  brighter.base_color *= 1.1;
  const artist::FitError e = artist::fit_error(table, brighter);
  EXPECT_NEAR(e.relative_rms, 0.1, 1e-4);
  EXPECT_NEAR(e.albedo_error, 0.1, 3e-3);
  ASSERT_EQ(e.angles_deg.size(), 6u);
  EXPECT_NEAR(e.table_albedo[0][0], 0.5, 2e-3);
}

}  // namespace
}  // namespace matlas
