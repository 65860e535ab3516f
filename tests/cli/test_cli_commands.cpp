// The commands called in-process through cli::run (cli/run.h): what they write, to which stream,
// and the files they produce, against the library's own answers.
#include <algorithm>
#include <filesystem>
#include <cmath>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "atlas/gi_basis.h"
#include "atlas/gi_density.h"
#include "atlas/model_material.h"
#include "atlas/sampling_fit.h"
#include "brdf/catalog.h"
#include "cli/in_process.h"
#include "formats/image_io.h"
#include "formats/merl_file.h"
#include "formats/synth_database.h"
#include "manifold/model.h"
#include "pathtrace/preview_scene.h"
#include "pathtrace/scene_spec.h"
#include "pathtrace/world.h"
#include "pathtrace/tracer.h"
#include "render/firefly_filter.h"
#include "render/image_basis.h"
#include "render/render.h"
#include "render/scene.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

namespace fs = std::filesystem;

using Output = test::CliOutput;
Output call(const std::vector<std::string>& args) { return test::call_matlas(args); }

#define EXPECT_CONTAINS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

class CliCommands : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("matlas-cli-commands");
    write_database(dir_->path() / "db", random_catalog(5, 11), null_progress(), MerlDims{8, 8, 16});
    const Output r = call({"build", (dir_->path() / "db").string(), "-o", model().string(), "--quiet", "--dim", "2"});
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_TRUE(r.err.empty()) << r.err;  // --quiet: the report only, on stdout
    ASSERT_NE(r.out.find("wrote " + model().string()), std::string::npos) << r.out;
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path model() { return dir_->path() / "m.matlas"; }
  static fs::path material(int i) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir_->path() / "db")) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files.at(static_cast<std::size_t>(i));
  }
  static inline test::TempDir* dir_ = nullptr;
};

TEST_F(CliCommands, HelpListsExportAndCallsEvalADeprecatedAlias) {
  const Output r = call({"--help"});
  EXPECT_EQ(r.code, 0);
  EXPECT_CONTAINS(r.out, "export");
  EXPECT_CONTAINS(r.out, "alias: eval, deprecated");
  EXPECT_TRUE(r.err.empty()) << r.err;
  const Output v = call({"--version"});
  EXPECT_EQ(v.code, 0);
  EXPECT_CONTAINS(v.out, "matlas ");
}

TEST_F(CliCommands, EvaluateSparseInducingPlacesTheStudysFitsSparsely) {
  // --sparse-inducing reaches the study's fits: their log-likelihood (the sparse bound) is not the
  // exact study's.
  auto study = [&](const std::string& name, const std::vector<std::string>& extra) {
    std::vector<std::string> args{"evaluate", (dir_->path() / "db").string(), "-o", (dir_->path() / name).string(),
                                  "--no-checks", "--quiet", "--dims", "2", "--layouts", "linear", "--materials", "2",
                                  "--pairs", "1"};
    args.insert(args.end(), extra.begin(), extra.end());
    return call(args);
  };
  auto first_row = [&](const std::string& name) {  // "layout,q,log_likelihood" of configs.csv's first row
    std::ifstream in(dir_->path() / name / "configs.csv");
    std::string header, row;
    std::getline(in, header);
    std::getline(in, row);
    std::size_t end = 0;
    for (int field = 0; field < 3; ++field) end = row.find(',', end) + 1;
    return row.substr(0, end - 1);
  };
  const Output exact = study("exact", {});
  ASSERT_EQ(exact.code, 0) << exact.err;
  const Output sparse = study("sparse", {"--sparse-inducing", "3"});
  ASSERT_EQ(sparse.code, 0) << sparse.err;
  EXPECT_EQ(first_row("exact").substr(0, 9), "linear,2,");
  EXPECT_EQ(first_row("sparse").substr(0, 9), "linear,2,");
  EXPECT_NE(first_row("exact"), first_row("sparse"));
}

TEST_F(CliCommands, ExportRefusesANonStandardGridUnderBothNames) {
  for (const char* command : {"export", "eval"}) {
    const Output r = call({command, model().string(), "--at", "0,0", "-o", (dir_->path() / "x.binary").string()});
    EXPECT_EQ(r.code, 1) << command;
    EXPECT_CONTAINS(r.err, "MERL files for other tools are 90x90x180");
  }
}

TEST(CliRender, AMerlFileIsTracedWithADensityFittedToItsOwnTable) {
  // A MERL file in a GI scene: by default its paths sample a density fitted to its own lobes (as a
  // model's are fitted to its database), --density fixed the former constant lobes; each image is
  // the library's trace with that density.
  test::TempDir t;
  write_database(t.path() / "db", random_catalog(1, 11), null_progress(), MerlDims{90, 90, 180});
  const fs::path file = *fs::directory_iterator(t.path() / "db");
  const BrdfTable table = read_merl(file);
  const render::TableMaterial material(table);
  const render::MaterialList bank({&material});
  pathtrace::TraceSettings s;
  s.width = 8;
  s.height = 6;
  s.spp = 2;
  const pathtrace::World box(pathtrace::load_scene("box", "sphere"));
  const auto rendered = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = {"render", file.string(), "--scene", "box", "--width", "8", "--height", "6",
                                     "--spp", "2", "-o", (t.path() / "out.exr").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    const Output r = call(args);
    EXPECT_EQ(r.code, 0) << r.err;
    return read_image(t.path() / "out.exr");
  };
  s.density = atlas::fit_gi_density(bank);
  const Image fitted = pathtrace::trace(box, &bank, s).full(0);
  EXPECT_EQ(rendered({}).rgb, fitted.rgb);
  EXPECT_EQ(rendered({"--density", "fitted"}).rgb, fitted.rgb);
  s.density = pathtrace::default_fixed_density();
  const Image fixed = pathtrace::trace(box, &bank, s).full(0);
  EXPECT_EQ(rendered({"--density", "fixed"}).rgb, fixed.rgb);
  EXPECT_NE(fitted.rgb, fixed.rgb) << "other densities, other samples";
}

TEST(CliBuild, NamesUpToTwentyFourInputsAndCountsMoreByFolder) {
  test::TempDir t;
  const fs::path few = t.path() / "few", many = t.path() / "many";
  const std::vector<SynthMaterial> all = random_catalog(33, 5);  // distinct names
  write_database(few, {all.begin(), all.begin() + 3}, null_progress(), MerlDims{8, 8, 16});
  write_database(many, {all.begin() + 3, all.end()}, null_progress(), MerlDims{8, 8, 16});
  const auto build = [&](std::vector<std::string> inputs) {
    inputs.insert(inputs.begin(), "build");
    for (const char* a : {"--dim", "1", "--max-iterations", "5", "-o"}) inputs.emplace_back(a);
    inputs.push_back((t.path() / "m.matlas").string());
    const Output r = call(inputs);
    EXPECT_EQ(r.code, 0) << r.err;
    return r.err;
  };
  const fs::path a_few = *fs::directory_iterator(few), a_many = *fs::directory_iterator(many);
  const std::string listed = build({few.string()});
  EXPECT_CONTAINS(listed, "manifold of 3 materials");
  EXPECT_CONTAINS(listed, "  " + a_few.string() + "\n");
  // 33 inputs: a line per folder, no file named.
  const std::string counted = build({few.string(), many.string()});
  EXPECT_CONTAINS(counted, "manifold of 33 materials");
  EXPECT_CONTAINS(counted, "  3 files in " + few.string() + "\n");
  EXPECT_CONTAINS(counted, "  30 files in " + many.string() + "\n");
  EXPECT_EQ(counted.find(a_few.filename().string()), std::string::npos) << counted;
  EXPECT_EQ(counted.find(a_many.filename().string()), std::string::npos) << counted;
}

TEST(CliExport, WritesTheMaterialAndEvalIsTheSameCommand) {
  test::TempDir t;
  write_database(t.path() / "db", random_catalog(3, 5), null_progress(), MerlDims{90, 90, 180});
  const fs::path m = t.path() / "m.matlas", input_file = *fs::directory_iterator(t.path() / "db");
  ASSERT_EQ(call({"build", (t.path() / "db").string(), "-o", m.string(), "--quiet", "--dim", "1"}).code, 0);
  const std::string name = input_file.stem().string();
  const fs::path a = t.path() / "a.binary", b = t.path() / "b.binary";
  const Output r = call({"export", m.string(), "--material", name, "-o", a.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_CONTAINS(r.out, "wrote " + a.string());
  ASSERT_EQ(call({"eval", m.string(), "--material", name, "-o", b.string()}).code, 0);
  const BrdfTable exported = read_merl(a), again = read_merl(b), input = read_merl(input_file);
  const auto x = exported.stored(), y = again.stored();
  EXPECT_TRUE(std::equal(x.begin(), x.end(), y.begin(), y.end()));
  // The model reproduces its inputs at their latent points (float32 storage).
  double worst = 0, peak = 0;
  for (std::size_t i = 0; i < input.stored().size(); ++i) {
    worst = std::max(worst, std::abs(exported.stored()[i] - input.stored()[i]));
    peak = std::max(peak, std::abs(input.stored()[i]));
  }
  EXPECT_LT(worst, 1e-4 * peak);
}

TEST_F(CliCommands, LatentJsonIsTheModelsNamesAndPoints) {
  const Output r = call({"latent", model().string(), "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const Model m = Model::open(model());
  EXPECT_EQ(j.at("q").get<int>(), 2);
  ASSERT_EQ(j.at("materials").size(), 5u);
  for (int i = 0; i < 5; ++i) {
    const auto& e = j["materials"][static_cast<std::size_t>(i)];
    EXPECT_EQ(e.at("name").get<std::string>(), material(i).stem().string());
    EXPECT_DOUBLE_EQ(e.at("x")[0].get<double>(), m.latent()(i, 0));
    EXPECT_DOUBLE_EQ(e.at("x")[1].get<double>(), m.latent()(i, 1));
  }
}

TEST_F(CliCommands, WeightsAtAMaterialSelectItAndSumToOne) {
  const std::string name = material(1).stem().string();
  const Output r = call({"weights", model().string(), "--material", name, "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j.at("sum").get<double>(), 1.0, 1e-9);
  EXPECT_LT(j.at("variance").get<double>(), 1e-3);
  for (const auto& w : j.at("weights"))
    EXPECT_NEAR(w.at("w").get<double>(), w.at("name") == name ? 1.0 : 0.0, 1e-3) << w.dump();
}

TEST_F(CliCommands, RenderTakesTheSamplerAndGrazingSamplesOptions) {
  // A database material rendered as the command does and as the library does with the same
  // settings: the options reach the renderer (each choice gives another image, equal to its own).
  const std::string name = material(2).stem().string();
  const Model m = Model::open(model());
  const atlas::ModelMaterial table(m, m.material_weights(m.index_of(name)));
  for (const auto& [sampler, enumerated, grazing] :
       {std::tuple{"light-and-lobe", render::Sampler::light_and_lobe, 4.0},
        std::tuple{"stratified", render::Sampler::stratified, 1.0},
        std::tuple{"independent", render::Sampler::independent, 2.0}}) {
    const fs::path out = dir_->path() / (std::string("r-") + sampler + ".exr");
    const Output r = call({"render", model().string(), "--material", name, "-o", out.string(), "--width", "16",
                           "--height", "16", "--spp", "4", "--env", "constant", "--sampler", sampler,
                           "--grazing-samples", std::to_string(grazing)});
    ASSERT_EQ(r.code, 0) << r.err;
    render::RenderSettings s;
    s.width = s.height = 16;
    s.spp = 4;
    s.sampler = enumerated;
    s.grazing_samples = grazing;
    render::SceneDescription d;
    d.environment = "constant";
    const Image expected = render::render(render::Scene(d), table, atlas::model_render_settings(m, s));
    const Image written = read_image(out);
    ASSERT_EQ(written.rgb.size(), expected.rgb.size());
    for (std::size_t i = 0; i < expected.rgb.size(); ++i)
      ASSERT_NEAR(written.rgb[i], expected.rgb[i], 1e-6 * (1.0 + std::abs(expected.rgb[i]))) << sampler << " value " << i;
  }
  EXPECT_NE(read_image(dir_->path() / "r-light-and-lobe.exr").rgb, read_image(dir_->path() / "r-stratified.exr").rgb);
}

TEST_F(CliCommands, RenderRefinesToATargetError) {
  // --target-error: passes until the estimated error inside the object is under the target; the
  // image then agrees with a long render of the library to about that error.
  const std::string name = material(1).stem().string();
  const fs::path out = dir_->path() / "refined.exr";
  const std::vector<std::string> common = {"render", model().string(), "--material", name, "-o", out.string(),
                                           "--width", "24", "--height", "24", "--env", "constant"};
  std::vector<std::string> args = common;
  args.insert(args.end(), {"--target-error", "0.01"});
  Output r = call(args);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_CONTAINS(r.out, "estimated error");
  EXPECT_EQ(r.out.find("reached before the target"), std::string::npos) << r.out;
  const Model m = Model::open(model());
  const atlas::ModelTableMaterial table(m, m.material_weights(m.index_of(name)));
  render::SceneDescription d;
  d.environment = "constant";
  const render::Scene scene(d);
  render::RenderSettings s;
  s.width = s.height = 24;
  s.spp = 4096;
  s.seed = 99;
  const Image reference = render::render(scene, table, atlas::model_render_settings(m, s));
  const std::vector<float> coverage = render::object_coverage(scene, s);
  const Image written = read_image(out);
  double squares = 0, signal = 0;
  for (std::size_t p = 0; p < coverage.size(); ++p)
    if (coverage[p] >= 1.0f)
      for (std::size_t c = 0; c < 3; ++c) {
        squares += std::pow(written.rgb[3 * p + c] - reference.rgb[3 * p + c], 2);
        signal += std::pow(reference.rgb[3 * p + c], 2);
      }
  EXPECT_LT(std::sqrt(squares / signal), 0.025);
  // A cap on the samples comes first: said so.
  args = common;
  args.insert(args.end(), {"--target-error", "0.0001", "--spp", "16"});
  r = call(args);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_CONTAINS(r.out, "16 spp");
  EXPECT_CONTAINS(r.out, "--spp reached before the target");
  // Bad targets and the integrators without refinement are refused.
  for (const std::vector<std::string>& extra : {std::vector<std::string>{"--target-error", "0"},
                                                {"--target-error", "1.5"},
                                                {"--target-error", "0.01", "--integrator", "path"}}) {
    args = common;
    args.insert(args.end(), extra.begin(), extra.end());
    r = call(args);
    EXPECT_NE(r.code, 0) << extra.back();
    EXPECT_CONTAINS(r.err, "--target-error");
  }
}

TEST_F(CliCommands, RenderIntegratorPathTracesThePreviewsScene) {
  // One scene, two integrators: --integrator path traces the preview's scene (every preview
  // option: ground, light, black background) as the library does with pathtrace::preview_scene.
  const std::string name = material(2).stem().string();
  const Model m = Model::open(model());
  const fs::path out = dir_->path() / "path.exr";
  const std::vector<std::string> args = {"render", model().string(), "--material", name, "-o", out.string(),
                                         "--width", "16", "--height", "12", "--spp", "4", "--env", "constant",
                                         "--ground", "--light", "0.3,1,0.5,2", "--black-background"};
  std::vector<std::string> path = args;
  path.insert(path.end(), {"--integrator", "path", "--max-depth", "2"});
  const Output r = call(path);
  ASSERT_EQ(r.code, 0) << r.err;
  render::SceneDescription d;
  d.environment = "constant";
  d.ground = true;
  d.camera.position = Vec3(0.0, 0.9, 3.9);  // --ground's camera
  d.lights.push_back({Vec3(0.3, 1, 0.5).normalized(), Rgb::Constant(2.0)});
  d.show_environment = false;
  const atlas::ModelTableMaterial table(m, m.material_weights(m.index_of(name)));
  const render::MaterialList bank({&table});
  pathtrace::TraceSettings t;
  t.width = 16;
  t.height = 12;
  t.spp = 4;
  t.max_depth = 2;
  t.density = atlas::fit_gi_density(m);
  const Image expected = pathtrace::trace(pathtrace::World(pathtrace::preview_scene(d)), &bank, t).full(0);
  const Image written = read_image(out);
  ASSERT_EQ(written.rgb.size(), expected.rgb.size());
  for (std::size_t i = 0; i < expected.rgb.size(); ++i)
    ASSERT_NEAR(written.rgb[i], expected.rgb[i], 1e-6 * (1.0 + std::abs(expected.rgb[i]))) << "value " << i;
  EXPECT_GT(*std::max_element(written.rgb.begin(), written.rgb.end()), 0.0f);

  std::vector<std::string> direct = args;
  direct.insert(direct.end(), {"--max-depth", "2"});
  const Output bad = call(direct);
  EXPECT_EQ(bad.code, 1);
  EXPECT_CONTAINS(bad.err, "--max-depth does not apply to --integrator direct");
  std::vector<std::string> other = args;
  other.insert(other.end(), {"--integrator", "photons"});
  EXPECT_CONTAINS(call(other).err, "--integrator must be direct or path");
}

TEST_F(CliCommands, OneRenderCommandForEverySceneAndBasis) {
  // render and basis cover what gi-render, gi-basis and gi did: a GI scene (--scene box) is
  // path-traced as the library traces it; a basis, image or GI, is composed at the point as the
  // library composes it; the former names are deprecated aliases of the same code.
  const Model m = Model::open(model());
  const Eigen::Vector2d x(0.1, -0.2);
  const std::string at = "0.1,-0.2";
  const auto path = [&](const char* name) { return (dir_->path() / name).string(); };
  // A GI scene, traced.
  const std::vector<std::string> traced = {"render", model().string(), "--at", at, "--scene", "box", "--width", "8",
                                           "--height", "6", "--spp", "2", "-o", path("gi.exr")};
  ASSERT_EQ(call(traced).code, 0);
  pathtrace::TraceSettings t;
  t.width = 8;
  t.height = 6;
  t.spp = 2;
  t.density = atlas::fit_gi_density(m);
  const pathtrace::World box(pathtrace::load_scene("box", "sphere"));
  const Image expected = pathtrace::trace(box, atlas::model_point_bank(m, m.weights(x)).get(), t).full(0);
  EXPECT_EQ(read_image(path("gi.exr")).rgb, expected.rgb);
  std::vector<std::string> former = traced;
  former[0] = "gi-render";
  former.back() = path("gi-former.exr");
  const Output old = call(former);
  ASSERT_EQ(old.code, 0) << old.err;
  EXPECT_CONTAINS(old.err, "matlas gi-render is deprecated");
  EXPECT_EQ(read_image(path("gi-former.exr")).rgb, expected.rgb);
  // An image basis of the previews' scene, composed.
  ASSERT_EQ(call({"basis", model().string(), "--env", "constant", "--width", "8", "--height", "8", "--spp", "2",
                  "--precision", "f32", "-o", path("image-basis.safetensors")})
                .code,
            0);
  ASSERT_EQ(call({"render", model().string(), "--at", at, "--basis", path("image-basis.safetensors"), "-o",
                  path("composed.exr")})
                .code,
            0);
  const render::ImageBasis image_basis = render::ImageBasis::open(path("image-basis.safetensors"));
  EXPECT_EQ(read_image(path("composed.exr")).rgb, image_basis.compose(m.weights(x)).rgb);
  // A GI basis, composed (part i1).
  ASSERT_EQ(call({"basis", model().string(), "--scene", "box", "--width", "8", "--height", "6", "--spp", "1", "-o",
                  path("gi-basis.safetensors")})
                .code,
            0);
  ASSERT_EQ(call({"render", model().string(), "--at", at, "--basis", path("gi-basis.safetensors"), "--part", "i1",
                  "-o", path("gi-composed.exr")})
                .code,
            0);
  const atlas::GiBasis gi_basis = atlas::GiBasis::load(path("gi-basis.safetensors"));
  EXPECT_EQ(read_image(path("gi-composed.exr")).rgb, gi_basis.compose(m.weights(x), atlas::GiBasis::Part::i1).rgb);
  // --remove-fireflies: the browser's drag image (render/firefly_filter.h), said by the command.
  const Output filtered = call({"render", model().string(), "--at", at, "--basis", path("gi-basis.safetensors"),
                                "--remove-fireflies", "-o", path("gi-filtered.exr")});
  ASSERT_EQ(filtered.code, 0) << filtered.err;
  Image expected_filtered = gi_basis.compose(m.weights(x));
  const int removed = render::remove_fireflies(expected_filtered);
  EXPECT_CONTAINS(filtered.out, "removed " + std::to_string(removed) + " fireflies");
  EXPECT_EQ(read_image(path("gi-filtered.exr")).rgb, expected_filtered.rgb);
  EXPECT_CONTAINS(call({"render", model().string(), "--at", at, "--remove-fireflies", "-o", path("n.exr")}).err,
                  "--remove-fireflies applies to --basis");
  // What does not apply is named.
  EXPECT_CONTAINS(call({"render", model().string(), "--at", at, "--basis", path("image-basis.safetensors"), "--spp",
                        "4", "-o", path("n.exr")})
                      .err,
                  "--spp does not apply to --basis");
  EXPECT_CONTAINS(call({"render", model().string(), "--at", at, "--basis", path("image-basis.safetensors"), "--part",
                        "i1", "-o", path("n.exr")})
                      .err,
                  "--part does not apply to an image basis");
  EXPECT_CONTAINS(call({"basis", model().string(), "--scene", "box", "--rank", "auto", "-o", path("n.safetensors")}).err,
                  "--rank does not apply to a GI basis");
  EXPECT_CONTAINS(call({"basis", model().string(), "--batch", "4", "-o", path("n.safetensors")}).err,
                  "--batch does not apply to the previews' scene");
}

TEST_F(CliCommands, ProjectFindsAnInputAndErrorsGoToTheErrorStream) {
  const Output r = call({"project", model().string(), material(3).string(), "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("nearest").get<std::string>(), material(3).stem().string());
  EXPECT_LT(j.at("relative_error").get<double>(), 1e-3);

  const Output bad = call({"project", model().string(), (dir_->path() / "absent.binary").string()});
  EXPECT_EQ(bad.code, 1);
  EXPECT_TRUE(bad.out.empty()) << bad.out;
  EXPECT_CONTAINS(bad.err, "matlas: error: ");
  EXPECT_CONTAINS(bad.err, "absent.binary");
}

TEST_F(CliCommands, UsageErrorsExitTwoNamingTheFlag) {
  const Output r = call({"weights", model().string(), "--at", "0,0", "--top", "-1"});
  EXPECT_EQ(r.code, 2);
  EXPECT_CONTAINS(r.err, "--top");
  EXPECT_EQ(call({"no-such-command"}).code, 2);
  EXPECT_EQ(call({}).code, 2);  // a command is required
}

TEST_F(CliCommands, InfoAndSynthWriteTheirReportsToOut) {
  test::TempDir t;
  const Output s = call({"synth", "-o", (t.path() / "db").string(), "--count", "2", "--seed", "3"});
  ASSERT_EQ(s.code, 0) << s.err;
  EXPECT_EQ(std::count(s.out.begin(), s.out.end(), '\n'), 2) << s.out;  // one line per file
  EXPECT_CONTAINS(s.err, "wrote 2 MERL files");
  const Output i = call({"info", material(0).string()});
  ASSERT_EQ(i.code, 0) << i.err;
  EXPECT_CONTAINS(i.out, material(0).string());
  EXPECT_CONTAINS(i.out, "dims            8 x 8 x 16");
}

}  // namespace
}  // namespace matlas
