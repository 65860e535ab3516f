#pragma once
// What the server suites serve: a model of `count` random synthetic materials on an 8x8x16 grid
// (q = 2), built in `dir` (its files in dir/db_folder), and image-basis previews of it (constant environment, sphere).
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "brdf/catalog.h"
#include "formats/synth_database.h"
#include "manifold/build.h"
#include "manifold/material_set.h"
#include "manifold/model.h"
#include "server/basis_previews.h"

namespace matlas::test {

inline Model build_small_model(const std::filesystem::path& dir, int count, std::uint64_t seed,
                               const std::string& name = "m.matlas", const std::string& db_folder = "db") {
  const auto db = dir / db_folder;
  write_database(db, random_catalog(count, seed), null_progress(), MerlDims{8, 8, 16});
  BuildOptions options;
  options.dim = 2;
  build_model(MaterialSet::open({db}), options, dir / name);
  return Model::open(dir / name);
}

inline std::shared_ptr<server::BasisPreviews> sphere_previews(const Model& model, int size, int spp) {
  server::BasisPreviewOptions po;
  po.environments = {"constant"};
  po.objects = {"sphere"};
  po.size = size;
  po.spp = spp;
  auto previews = std::make_shared<server::BasisPreviews>(model, po);
  previews->prepare_default();
  return previews;
}

}  // namespace matlas::test
