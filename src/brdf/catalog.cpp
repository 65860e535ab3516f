#include "brdf/catalog.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <unordered_map>

namespace matlas {

namespace {

/// Reflectances at normal incidence of metals (linear RGB, as tabulated for Schlick's
/// approximation in physically based renderers, e.g. Hoffman's and Lagarde's charts).
struct Metal {
  const char* name;
  Rgb f0;
};
const Metal kMetals[] = {
    {"gold", Rgb(1.000, 0.782, 0.344)},     {"copper", Rgb(0.955, 0.638, 0.538)},
    {"silver", Rgb(0.972, 0.960, 0.915)},   {"aluminium", Rgb(0.913, 0.922, 0.924)},
    {"chrome", Rgb(0.549, 0.556, 0.554)},   {"iron", Rgb(0.562, 0.565, 0.578)},
    {"nickel", Rgb(0.660, 0.609, 0.526)},   {"titanium", Rgb(0.542, 0.497, 0.449)},
    {"platinum", Rgb(0.673, 0.637, 0.585)}, {"brass", Rgb(0.910, 0.778, 0.423)},
};

Rgb metal(const char* name) {
  for (const Metal& m : kMetals)
    if (std::string(name) == m.name) return m.f0;
  return Rgb::Constant(0.9);
}

/// Diffuse reflectances (linear RGB) of the named colours used by the demo catalogue.
Rgb paint(const std::string& name) {
  static const std::unordered_map<std::string, Rgb> paints = {
      {"red", Rgb(0.70, 0.05, 0.04)},    {"orange", Rgb(0.80, 0.28, 0.04)},
      {"yellow", Rgb(0.80, 0.62, 0.06)}, {"green", Rgb(0.10, 0.45, 0.07)},
      {"teal", Rgb(0.04, 0.38, 0.36)},   {"blue", Rgb(0.04, 0.10, 0.60)},
      {"purple", Rgb(0.30, 0.06, 0.50)}, {"pink", Rgb(0.85, 0.32, 0.42)},
      {"white", Rgb(0.85, 0.85, 0.85)},  {"grey", Rgb(0.22, 0.22, 0.22)},
      {"black", Rgb(0.02, 0.02, 0.02)},  {"brown", Rgb(0.28, 0.12, 0.05)},
  };
  return paints.at(name);
}

SynthMaterial conductor(const char* metal_name, double alpha) {
  const AnalyticBrdf brdf = GgxConductor{metal(metal_name), alpha};
  return {material_name(brdf, metal_name), brdf};
}

SynthMaterial plastic(const std::string& colour, double alpha) {
  const AnalyticBrdf brdf = RoughPlastic{paint(colour), alpha, 1.5, 1.0};
  return {material_name(brdf, colour), brdf};
}

SynthMaterial matte(const std::string& colour) {
  const AnalyticBrdf brdf = Lambertian{paint(colour)};
  return {material_name(brdf, colour), brdf};
}

SynthMaterial phong(const std::string& colour, double exponent, double ks) {
  const AnalyticBrdf brdf = BlinnPhong{Rgb::Constant(ks), exponent, paint(colour) * (1.0 - ks)};
  return {material_name(brdf, colour), brdf};
}

/// SplitMix64 (Steele, Lea, Flood 2014): a tiny generator whose output is fixed by its definition.
class SplitMix64 {
public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n).
  int below(int n) { return std::min(n - 1, static_cast<int>(uniform() * n)); }

private:
  std::uint64_t state_;
};

double round_to(double v, double step) { return std::round(v / step) * step; }

/// Linear RGB from hue (turns), saturation and value applied in display (gamma 2.2) space.
Rgb colour_from_hsv(double hue, double sat, double value) {
  const double h6 = 6.0 * (hue - std::floor(hue));
  const int sector = std::min(5, static_cast<int>(h6));
  const double f = h6 - sector;
  const double p = value * (1 - sat), q = value * (1 - sat * f), t = value * (1 - sat * (1 - f));
  Rgb g;
  switch (sector) {
    case 0: g = Rgb(value, t, p); break;
    case 1: g = Rgb(q, value, p); break;
    case 2: g = Rgb(p, value, t); break;
    case 3: g = Rgb(p, q, value); break;
    case 4: g = Rgb(t, p, value); break;
    default: g = Rgb(value, p, q); break;
  }
  return g.pow(2.2);
}

Rgb round_colour(const Rgb& c) {
  return c.unaryExpr([](double v) { return std::clamp(round_to(v, 0.001), 0.0, 1.0); });
}

/// Perceptual roughness r uniform in [0.1, 0.8], alpha = r^2 rounded to 0.001 (so that the name,
/// which shows alpha, is exact).
double random_alpha(SplitMix64& rng) {
  const double r = rng.uniform(0.1, 0.8);
  return std::max(0.005, round_to(r * r, 0.001));
}

/// Three draws in a defined order (function arguments are evaluated in an unspecified order, so
/// every draw below is sequenced through a named variable or a braced list).
Rgb uniform_rgb(SplitMix64& rng, double lo, double hi) {
  const double r = rng.uniform(lo, hi), g = rng.uniform(lo, hi), b = rng.uniform(lo, hi);
  return {r, g, b};
}

/// A random display colour: mostly saturated, sometimes nearly grey.
Rgb random_colour(SplitMix64& rng, double value_lo, double value_hi) {
  const double hue = rng.uniform();
  const bool greyish = rng.uniform() < 0.2;
  const double sat = greyish ? rng.uniform(0.0, 0.1) : rng.uniform(0.3, 1.0);
  const double value = rng.uniform(value_lo, value_hi);
  return round_colour(colour_from_hsv(hue, sat, value));
}

SynthMaterial random_material(SplitMix64& rng) {
  const double family = rng.uniform();
  if (family < 0.35) {  // conductor: a known metal, slightly varied, or a tinted (anodised) one
    if (rng.uniform() < 0.7) {
      const Metal& m = kMetals[rng.below(static_cast<int>(std::size(kMetals)))];
      const Rgb f0 = round_colour(m.f0 + uniform_rgb(rng, -0.02, 0.02));
      const AnalyticBrdf brdf = GgxConductor{f0, random_alpha(rng)};
      return {material_name(brdf, m.name), brdf};
    }
    const double hue = rng.uniform();
    const double sat = rng.uniform(0.3, 0.8);
    const double value = rng.uniform(0.75, 1.0);
    const Rgb f0 = round_colour(colour_from_hsv(hue, sat, value));
    const AnalyticBrdf brdf = GgxConductor{f0, random_alpha(rng)};
    return {material_name(brdf, colour_name(f0)), brdf};
  }
  const Rgb colour = random_colour(rng, 0.15, 0.95);
  const std::string name = colour_name(colour);
  if (family < 0.70) {
    const AnalyticBrdf brdf = RoughPlastic{colour, random_alpha(rng), 1.5, 1.0};
    return {material_name(brdf, name), brdf};
  }
  if (family < 0.82) {
    const AnalyticBrdf brdf = Lambertian{colour};
    return {material_name(brdf, name), brdf};
  }
  const double ks = round_to(rng.uniform(0.02, 0.2), 0.001);
  const double exponent = std::round(std::exp(rng.uniform(std::log(10.0), std::log(5000.0))));
  const AnalyticBrdf brdf = BlinnPhong{Rgb::Constant(ks), exponent, round_colour(colour * (1.0 - ks))};
  return {material_name(brdf, name), brdf};
}

}  // namespace

std::string parameter_text(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", value);
  std::string s = buf;
  const std::size_t dot = s.find('.');
  while (s.size() > dot + 3 && s.back() == '0') s.pop_back();
  return s;
}

std::string material_name(const AnalyticBrdf& brdf, const std::string& colour) {
  std::string name = family_name(brdf) + "-" + colour;
  if (const auto* g = std::get_if<GgxConductor>(&brdf)) name += "-a" + parameter_text(g->alpha);
  if (const auto* p = std::get_if<RoughPlastic>(&brdf)) name += "-a" + parameter_text(p->alpha);
  if (const auto* b = std::get_if<BlinnPhong>(&brdf)) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "-n%g", b->exponent);
    name += buf;
  }
  return name;
}

std::string colour_name(const Rgb& linear) {
  const Rgb g = linear.max(0.0).pow(1.0 / 2.2);  // display values: hue and value as seen
  const double hi = g.maxCoeff(), lo = g.minCoeff();
  const double sat = hi > 0 ? (hi - lo) / hi : 0.0;
  if (hi < 0.2) return "black";
  if (sat < 0.18) return hi > 0.8 ? "white" : "grey";
  double hue;  // degrees
  if (hi == g[0]) hue = 60.0 * std::fmod((g[1] - g[2]) / (hi - lo) + 6.0, 6.0);
  else if (hi == g[1]) hue = 60.0 * ((g[2] - g[0]) / (hi - lo) + 2.0);
  else hue = 60.0 * ((g[0] - g[1]) / (hi - lo) + 4.0);
  if (hue < 15 || hue >= 345) return "red";
  if (hue < 45) return hi < 0.6 ? "brown" : "orange";
  if (hue < 70) return hi < 0.55 ? "olive" : "yellow";
  if (hue < 160) return "green";
  if (hue < 200) return "teal";
  if (hue < 255) return "blue";
  if (hue < 290) return "purple";
  return "pink";
}

void make_names_unique(std::vector<SynthMaterial>& catalog) {
  std::set<std::string> taken;
  for (const SynthMaterial& m : catalog) taken.insert(m.name);
  std::set<std::string> seen;
  for (SynthMaterial& m : catalog) {
    if (seen.insert(m.name).second) continue;
    for (int n = 2;; ++n) {
      const std::string candidate = m.name + "-" + std::to_string(n);
      if (!taken.count(candidate)) {
        m.name = candidate;
        taken.insert(candidate);
        seen.insert(candidate);
        break;
      }
    }
  }
}

std::vector<SynthMaterial> demo_catalog() {
  std::vector<SynthMaterial> c = {
      conductor("gold", 0.05),      conductor("gold", 0.15),       conductor("gold", 0.35),
      conductor("copper", 0.08),    conductor("copper", 0.25),     conductor("silver", 0.03),
      conductor("silver", 0.20),    conductor("aluminium", 0.10),  conductor("aluminium", 0.40),
      conductor("chrome", 0.02),    conductor("chrome", 0.10),     conductor("iron", 0.30),
      conductor("titanium", 0.20),  conductor("brass", 0.12),      conductor("platinum", 0.06),
      plastic("red", 0.05),         plastic("red", 0.30),          plastic("blue", 0.10),
      plastic("green", 0.20),       plastic("yellow", 0.08),       plastic("white", 0.15),
      plastic("black", 0.03),       plastic("orange", 0.40),       plastic("purple", 0.12),
      matte("white"),               matte("grey"),                 matte("teal"),
      matte("brown"),               phong("blue", 200, 0.08),      phong("white", 50, 0.10),
      phong("red", 1000, 0.05),     phong("pink", 20, 0.15),
  };
  make_names_unique(c);
  return c;
}

std::vector<SynthMaterial> random_catalog(int count, std::uint64_t seed) {
  std::vector<SynthMaterial> c;
  c.reserve(static_cast<std::size_t>(std::max(0, count)));
  SplitMix64 rng(seed);
  // Parameters are rounded for readable names, so two draws can coincide: redraw duplicates
  // (identical materials cannot be placed on a map).
  std::set<std::string> seen;
  for (int n = 0; n < count; ++n) {
    SynthMaterial m = random_material(rng);
    for (int attempt = 0; attempt < 1000 && !seen.insert(describe(m.brdf)).second; ++attempt)
      m = random_material(rng);
    c.push_back(std::move(m));
  }
  make_names_unique(c);
  return c;
}

}  // namespace matlas
