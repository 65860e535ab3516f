#pragma once
// The model's header metadata (Model::metadata(), a JSON object: names, kernel, optimiser,
// likelihood, sources, layout, interpolation, ...). model.h only forward-declares the JSON type;
// code that reads the metadata includes this header.
#include <string>

#include <nlohmann/json.hpp>

#include "manifold/model.h"

namespace matlas {

/// The model's display name: metadata "name" when it is a string, else the file's stem.
std::string model_name(const Model& model);

}  // namespace matlas
