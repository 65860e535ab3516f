#include "manifold/model_metadata.h"

namespace matlas {

std::string model_name(const Model& model) {
  const nlohmann::json& meta = model.metadata();
  if (meta.contains("name") && meta["name"].is_string()) return meta["name"].get<std::string>();
  return model.path().stem().string();
}

}  // namespace matlas
