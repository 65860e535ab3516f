#pragma once
// Writing a synthetic MERL database: each material of a catalogue (brdf/catalog.h) is tabulated on
// the MERL grid (brdf/tabulate.h) and written atomically as DIR/NAME.binary.
#include <filesystem>
#include <vector>

#include "brdf/catalog.h"
#include "brdf/merl_grid.h"
#include "core/progress.h"

namespace matlas {

/// Tabulates and writes every material of `catalog` into `dir` (created with its parents if
/// needed), reporting one progress unit per material, and returns the written paths in catalogue
/// order. Existing files of the same names are replaced. `dims` other than MERL's 90x90x180 are
/// for tests only (other tools cannot read them).
/// Throws matlas::Error if `dir` cannot be created or is not a folder, if two materials share a
/// name, if a name is not a plain file name, or if a material's parameters are invalid (checked
/// for the whole catalogue before anything is written).
std::vector<std::filesystem::path> write_database(const std::filesystem::path& dir,
                                                  const std::vector<SynthMaterial>& catalog,
                                                  ProgressSink& progress = null_progress(),
                                                  MerlDims dims = {});

}  // namespace matlas
