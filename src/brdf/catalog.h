#pragma once
// Catalogues of synthetic materials: named analytic BRDFs from which a MERL-like database is made
// (formats/synth_database.h writes them; `matlas synth` is the command).
//
// Names say what a material is: FAMILY-COLOUR[-PARAMETER], e.g. "ggx-gold-a0.20",
// "plastic-red-a0.10", "lambert-white", "phong-blue-n200", where aX is the GGX alpha and nX the
// Blinn-Phong exponent. Names are unique within a catalogue (a repeated name gets "-2", "-3", ...),
// use only [a-z0-9.-], and the file of a material is NAME.binary.
#include <cstdint>
#include <string>
#include <vector>

#include "brdf/analytic.h"

namespace matlas {

struct SynthMaterial {
  std::string name;
  AnalyticBrdf brdf;

  std::string file_name() const { return name + ".binary"; }
};

/// A fixed, pleasant set of about 30 materials: gold, copper, silver, aluminium, chrome and other
/// conductors at several roughnesses, coloured plastics, matte paints and Blinn-Phong materials.
std::vector<SynthMaterial> demo_catalog();

/// `count` materials drawn from `seed`: the same seed always gives the same catalogue (on every
/// platform: the generator and the draws are defined here, not by the standard library's
/// distributions). Families, colours and roughnesses are varied; names are unique.
std::vector<SynthMaterial> random_catalog(int count, std::uint64_t seed);

/// The name of a material: FAMILY-COLOUR, plus "-aALPHA" (ggx, plastic) or "-nEXPONENT" (phong).
std::string material_name(const AnalyticBrdf& brdf, const std::string& colour);

/// Short text of a parameter value for names: 3 decimals, trailing zeros dropped down to two
/// decimals (0.2 -> "0.20", 0.05 -> "0.05", 0.125 -> "0.125").
std::string parameter_text(double value);

/// A colour word for a linear RGB reflectance ("red", "teal", "white", "grey", "black", ...).
std::string colour_name(const Rgb& linear);

/// Appends "-2", "-3", ... to repeated names so that every name is unique.
void make_names_unique(std::vector<SynthMaterial>& catalog);

}  // namespace matlas
