// Synthetic material catalogues: names, determinism, validity.
#include <regex>
#include <set>

#include <gtest/gtest.h>

#include "brdf/catalog.h"

namespace matlas {
namespace {

std::set<std::string> names_of(const std::vector<SynthMaterial>& c) {
  std::set<std::string> names;
  for (const auto& m : c) names.insert(m.name);
  return names;
}

bool same_brdf(const AnalyticBrdf& a, const AnalyticBrdf& b) { return describe(a) == describe(b); }

TEST(SynthCatalog, DemoPresetHasAboutThirtyValidUniquelyNamedMaterialsOfEveryFamily) {
  const auto demo = demo_catalog();
  EXPECT_GE(demo.size(), 25u);
  EXPECT_LE(demo.size(), 40u);
  EXPECT_EQ(names_of(demo).size(), demo.size());
  std::set<std::string> families;
  const std::regex pattern("(ggx|plastic)-[a-z]+-a[0-9]\\.[0-9]{2,3}|lambert-[a-z]+|phong-[a-z]+-n[0-9]+");
  for (const auto& m : demo) {
    EXPECT_NO_THROW(validate(m.brdf)) << m.name;
    EXPECT_TRUE(std::regex_match(m.name, pattern)) << m.name;
    families.insert(family_name(m.brdf));
  }
  EXPECT_EQ(families.size(), 4u);
  for (const char* expected : {"ggx-gold-a0.15", "ggx-chrome-a0.02", "plastic-red-a0.05", "lambert-white",
                               "phong-blue-n200"})
    EXPECT_TRUE(names_of(demo).count(expected)) << expected;
}

TEST(SynthCatalog, RandomCatalogueIsDeterministicInItsSeed) {
  const auto a = random_catalog(40, 1234), b = random_catalog(40, 1234), c = random_catalog(40, 1235);
  ASSERT_EQ(a.size(), 40u);
  int differences = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].name, b[i].name);
    EXPECT_TRUE(same_brdf(a[i].brdf, b[i].brdf));
    differences += !same_brdf(a[i].brdf, c[i].brdf);
  }
  EXPECT_GT(differences, 30);
  // A prefix of a longer draw is the shorter draw (apart from de-duplicated names).
  const auto shorter = random_catalog(10, 1234);
  for (std::size_t i = 0; i < shorter.size(); ++i) EXPECT_TRUE(same_brdf(shorter[i].brdf, a[i].brdf));
}

TEST(SynthCatalog, RandomCatalogueIsValidVariedAndUniquelyNamed) {
  const auto c = random_catalog(300, 99);
  EXPECT_EQ(names_of(c).size(), c.size());
  std::set<std::string> families, colours;
  for (const auto& m : c) {
    EXPECT_NO_THROW(validate(m.brdf)) << m.name;
    families.insert(family_name(m.brdf));
    colours.insert(m.name.substr(m.name.find('-') + 1, m.name.find('-', m.name.find('-') + 1) - m.name.find('-') - 1));
    EXPECT_EQ(m.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789.-"), std::string::npos) << m.name;
  }
  EXPECT_EQ(families.size(), 4u);
  EXPECT_GE(colours.size(), 10u);
}

TEST(SynthCatalog, RepeatedNamesGetNumberedSuffixes) {
  std::vector<SynthMaterial> c = {{"a", Lambertian{}}, {"a", Lambertian{}}, {"a-2", Lambertian{}}, {"a", Lambertian{}}};
  make_names_unique(c);
  EXPECT_EQ(c[0].name, "a");
  EXPECT_EQ(c[1].name, "a-3");  // "a-2" is taken by a later material
  EXPECT_EQ(c[2].name, "a-2");
  EXPECT_EQ(c[3].name, "a-4");
}

TEST(SynthCatalog, NamesShowTheParameters) {
  EXPECT_EQ(parameter_text(0.2), "0.20");
  EXPECT_EQ(parameter_text(0.05), "0.05");
  EXPECT_EQ(parameter_text(0.125), "0.125");
  EXPECT_EQ(material_name(GgxConductor{Rgb::Ones(), 0.2}, "gold"), "ggx-gold-a0.20");
  EXPECT_EQ(material_name(BlinnPhong{Rgb::Constant(0.1), 200, Rgb::Zero()}, "blue"), "phong-blue-n200");
  EXPECT_EQ(material_name(Lambertian{}, "white"), "lambert-white");
  EXPECT_EQ(colour_name(Rgb(0.7, 0.05, 0.04)), "red");
  EXPECT_EQ(colour_name(Rgb(0.04, 0.10, 0.60)), "blue");
  EXPECT_EQ(colour_name(Rgb(0.85, 0.85, 0.85)), "white");
  EXPECT_EQ(colour_name(Rgb(0.01, 0.01, 0.012)), "black");
}

}  // namespace
}  // namespace matlas

namespace matlas {
namespace {

TEST(SynthCatalog, RandomCataloguesHaveNoIdenticalMaterials) {
  // Rounded parameters made seeds 1 and 2 draw the same Lambertian twice at n = 100.
  for (std::uint64_t seed : {1, 2, 3, 7}) {
    std::set<std::string> seen;
    for (const auto& m : random_catalog(100, seed)) EXPECT_TRUE(seen.insert(describe(m.brdf)).second) << seed;
  }
}

}  // namespace
}  // namespace matlas
