// The `matlas` command's outputs, second round of hardening (issue 28): no command writes over one
// of its inputs (by any path, symlink or hard link), no temporary file is opened through a planted
// symlink, no output is committed from a model truncated while it was read, and crafted model
// metadata (nested 100,000 deep, a permuted grid) is refused when the model is opened.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <chrono>
#include <thread>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "brdf/catalog.h"
#include "cli/in_process.h"
#include "cli/model_surgery.h"
#include "core/error.h"
#include "formats/mapping_watch.h"
#include "formats/synth_database.h"
#include "manifold/model.h"
#include "pathtrace/scene_spec.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

namespace fs = std::filesystem;

struct OutputsRun {
  int code = -1;
  std::string out;  ///< stdout and stderr
};

OutputsRun run_matlas(const std::vector<std::string>& args) {
  const test::CliOutput r = test::call_matlas(args);
  return {r.code, r.out + r.err};
}

std::string file_bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

#define EXPECT_CONTAINS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

class CliOutputs : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("matlas-cli-outputs");
    write_database(dir_->path() / "db", random_catalog(5, 3), null_progress(), MerlDims{8, 8, 16});
    const OutputsRun r = run_matlas({"build", (dir_->path() / "db").string(), "-o", model().string(), "--quiet", "--dim", "2"});
    ASSERT_EQ(r.code, 0) << r.out;
    const std::vector<std::string> gi = {"basis", model().string(), "--scene", "box", "--width", "4", "--height",
                                         "3", "--spp", "1", "-o", gi_basis().string()};
    ASSERT_EQ(run_matlas(gi).code, 0);
    std::ofstream(scene()) << pathtrace::scene_to_json(pathtrace::load_scene("box", "sphere")).dump();
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path model() { return dir_->path() / "m.matlas"; }
  static fs::path gi_basis() { return dir_->path() / "gi.safetensors"; }
  static fs::path scene() { return dir_->path() / "scene.json"; }
  static fs::path first_material() {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir_->path() / "db")) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files.front();
  }
  static inline test::TempDir* dir_ = nullptr;
};

// ---- An output that is one of the inputs: refused by every command that writes a file, whether
// it is named as given, through a symlink or through a hard link; the input is left intact.
TEST_F(CliOutputs, NoCommandWritesOverOneOfItsInputs) {
  test::TempDir t;
  const std::string m = model().string(), material = first_material().string(), gi = gi_basis().string();
  const std::vector<std::string> tiny = {"--width", "4", "--height", "3", "--spp", "1"};
  struct Case {
    fs::path input;                 ///< the input the output names
    std::vector<std::string> args;  ///< the command, "OUT" standing for the output
  };
  auto with = [](std::vector<std::string> a, const std::vector<std::string>& more) {
    a.insert(a.end(), more.begin(), more.end());
    return a;
  };
  const std::vector<Case> cases = {
      {model(), {"export", m, "--at", "0,0", "-o", "OUT"}},
      {model(), {"zonal", m, "--bands", "2", "--theta-o", "4", "-o", "OUT"}},
      {first_material(), {"zonal", (dir_->path() / "db").string(), "--bands", "2", "--theta-o", "4", "-o", "OUT"}},
      {model(), with({"basis", m, "--scene", "box", "-o", "OUT"}, tiny)},
      {scene(), with({"basis", m, "--scene", scene().string(), "-o", "OUT"}, tiny)},
      {model(), {"render", m, "--at", "0,0", "--basis", gi, "-o", "OUT"}},
      {gi_basis(), {"render", m, "--at", "0,0", "--basis", gi, "-o", "OUT"}},
      {model(), with({"render", m, "--at", "0,0", "--scene", "box", "-o", "OUT"}, tiny)},
      {scene(), with({"render", m, "--at", "0,0", "--scene", scene().string(), "-o", "OUT"}, tiny)},
      {model(), with({"basis", m, "--env", "constant", "-o", "OUT"}, tiny)},
      {model(), with({"render", m, "--at", "0,0", "--env", "constant", "-o", "OUT"}, tiny)},
      {first_material(), with({"render", material, "--env", "constant", "-o", "OUT"}, tiny)},
      {model(), {"map", m, "--size", "16", "-o", "OUT"}},
      {gi_basis(), {"map", m, "--size", "16", "--layer", "image", "--basis", gi, "-o", "OUT"}},
      {model(), with({"gallery", m, "--env", "constant", "--random", "1", "--real", "1", "-o", "OUT"}, tiny)},
      {model(), with({"gallery", m, "--env", "constant", "--random", "1", "--real", "1", "-o",
                      (t.path() / "g.png").string(), "--key", "OUT"}, tiny)},
      {model(), {"evaluate", m, "--no-study", "--quiet", "-o", "OUT"}},
      {first_material(), {"build", (dir_->path() / "db").string(), "--quiet", "-o", "OUT"}},
  };
  for (const Case& c : cases) {
    const std::string before = file_bytes_of(c.input);
    const fs::path symlink = t.path() / ("link" + c.input.extension().string());
    const fs::path hardlink = t.path() / ("hard" + c.input.extension().string());
    fs::remove(symlink);
    fs::remove(hardlink);
    fs::create_symlink(c.input, symlink);
    fs::create_hard_link(c.input, hardlink);
    for (const fs::path& out : {c.input, symlink, hardlink}) {
      std::vector<std::string> args = c.args;
      std::replace(args.begin(), args.end(), std::string("OUT"), out.string());
      const OutputsRun r = run_matlas(args);
      EXPECT_EQ(r.code, 1) << args[0] << " -o " << out << ": " << r.out;
      EXPECT_CONTAINS(r.out, "is one of the inputs");
      EXPECT_EQ(file_bytes_of(c.input), before) << args[0] << " -o " << out << " changed " << c.input;
    }
  }
  EXPECT_NO_THROW(Model::open(model()));
}

TEST_F(CliOutputs, GalleryRefusesAKeyThatIsItsPicture) {
  test::TempDir t;
  const std::string png = (t.path() / "g.png").string();
  const OutputsRun r = run_matlas({"gallery", model().string(), "--env", "constant", "--random", "1", "--real", "1", "--width",
                        "4", "--height", "3", "--spp", "1", "-o", png, "--key", png});
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_CONTAINS(r.out, "is the output picture");
  EXPECT_FALSE(fs::exists(png));
}

TEST_F(CliOutputs, GalleryRefinesItsCellsToATargetError) {
  test::TempDir t;
  const std::string png = (t.path() / "g.png").string();
  OutputsRun r = run_matlas({"gallery", model().string(), "--env", "constant", "--random", "1", "--real", "1", "--width",
                             "24", "--height", "24", "--target-error", "0.05", "-o", png});
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "cells refined: ");
  EXPECT_EQ(r.out.find("reached before the target"), std::string::npos) << r.out;
  r = run_matlas({"gallery", model().string(), "--env", "constant", "--random", "1", "--real", "1", "--width", "24",
                  "--height", "24", "--target-error", "0.05", "--basis", png, "-o", (t.path() / "h.png").string()});
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_CONTAINS(r.out, "--target-error");
}

// ---- The temporary output name is predictable (OUT.tmp-PID): a symlink planted there must not
// make the command write through it.
TEST_F(CliOutputs, ASymlinkPlantedAtTheTemporaryNameIsNotFollowed) {
  test::TempDir t;
  const fs::path victim = t.path() / "victim.txt", out = t.path() / "z.safetensors";
  std::ofstream(victim) << "precious";
  fs::create_symlink(victim, out.string() + ".tmp-" + std::to_string(::getpid()));  // in-process: our pid
  const OutputsRun r = run_matlas({"zonal", model().string(), "--bands", "2", "--theta-o", "4", "-o", out.string()});
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(file_bytes_of(victim), "precious");
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(out)));
  EXPECT_GT(fs::file_size(out), 0u);
}

// ---- A model truncated while it is read reads as zeros where its pages vanished: whatever was
// computed from it is wrong. No command commits an output (nor exits 0) once that happened.
TEST_F(CliOutputs, NoOutputIsCommittedFromAModelTruncatedWhileItWasRead) {
  test::TempDir t;
  const fs::path victim = t.path() / "victim.matlas";
  fs::copy_file(model(), victim);
  {
    // The model of a command, truncated after it was opened (as `cp` over it does) and then read.
    const Model opened = Model::open(victim);
    fs::resize_file(victim, fs::file_size(victim) / 2);
    (void)opened.table(opened.material_weights(0));
    ASSERT_GT(opened.mapping_faults(), 0u) << "the truncation was not seen";
    const MappingFaultWatch watch;
    try {
      watch.check();
      ADD_FAILURE() << "the watch did not see the truncated mapping";
    } catch (const Error& e) {
      EXPECT_CONTAINS(std::string(e.what()), victim.string() + ": the file changed or was truncated while it was read");
    }
    // Every command that writes refuses its output, and those that print fail.
    const std::vector<std::string> tiny = {"--width", "4", "--height", "3", "--spp", "1"};
    const fs::path out = t.path() / "out";
    for (std::vector<std::string> args : std::vector<std::vector<std::string>>{
             {"zonal", model().string(), "--bands", "2", "--theta-o", "4", "-o", out.string() + ".safetensors"},
             {"render", model().string(), "--at", "0,0", "--env", "constant", "-o", out.string() + ".png", "--width",
              "4", "--height", "3", "--spp", "1"},
             {"map", model().string(), "--size", "16", "-o", out.string() + ".png"},
             {"render", model().string(), "--at", "0,0", "--basis", gi_basis().string(), "-o", out.string() + ".exr"},
             {"weights", model().string(), "--at", "0,0"}}) {
      const OutputsRun r = run_matlas(args);
      EXPECT_EQ(r.code, 1) << args[0] << ": " << r.out;
      EXPECT_CONTAINS(r.out, victim.string() + ": the file changed or was truncated while it was read");
      for (const char* ext : {".safetensors", ".png", ".exr"})
        EXPECT_FALSE(fs::exists(out.string() + ext)) << args[0];
    }
  }
  // Once the damaged mapping is closed before a command starts, nothing of it remains.
  const OutputsRun r = run_matlas({"weights", model().string(), "--at", "0,0"});
  EXPECT_EQ(r.code, 0) << r.out;
}

/// Whether process `pid` has `path` memory-mapped.
bool maps_file(pid_t pid, const fs::path& path) {
  std::ifstream maps("/proc/" + std::to_string(pid) + "/maps");
  const std::string text((std::istreambuf_iterator<char>(maps)), std::istreambuf_iterator<char>());
  return text.find(path.string()) != std::string::npos;
}

// The same as a user meets it: `matlas zonal` on a full-size model that is truncated (as `cp` over
// it would) while the command reads it. Without the check it wrote coefficients from zeros and
// exited 0.
TEST(CliTruncation, AModelTruncatedDuringACommandGivesNoOutput) {
  test::TempDir t;
  write_database(t.path() / "db", random_catalog(3, 5), null_progress(), MerlDims{90, 90, 180});
  const fs::path built = t.path() / "built.matlas", model = t.path() / "m.matlas", out = t.path() / "z.safetensors",
                 log = t.path() / "log.txt";
  ASSERT_EQ(run_matlas({"build", (t.path() / "db").string(), "-o", built.string(), "--quiet", "--dim", "1"}).code, 0);
  bool mid_command = false;
  // The truncation must land after the model was opened (else the open refuses the file, which
  // proves nothing here): waited for, then retried later if it came too early.
  for (const int delay_ms : {50, 200, 800}) {
    fs::copy_file(built, model, fs::copy_options::overwrite_existing);
    const pid_t pid = ::fork();
    if (pid == 0) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      ::execl(MATLAS_EXE, MATLAS_EXE, "zonal", model.c_str(), "-o", out.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    const auto start = std::chrono::steady_clock::now();
    while (!maps_file(pid, model) && std::chrono::steady_clock::now() - start < std::chrono::seconds(30))
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    fs::resize_file(model, fs::file_size(model) / 4);
    int status = 0;
    ::waitpid(pid, &status, 0);
    const std::string text = file_bytes_of(log);
    ASSERT_TRUE(WIFEXITED(status)) << text;
    EXPECT_NE(WEXITSTATUS(status), 0) << "a truncated model gave an answer: " << text;
    EXPECT_FALSE(fs::exists(out)) << text;
    if (text.find(model.string() + ": the file changed or was truncated while it was read") != std::string::npos) {
      mid_command = true;
      break;
    }
  }
  EXPECT_TRUE(mid_command) << "every truncation came before the model was opened, or after the command ended";
}

// ---- Crafted metadata: refused on open, naming the file
std::string nested_metadata(const fs::path& model, int depth) {
  std::ifstream in(model, std::ios::binary);
  std::uint64_t length = 0;
  in.read(reinterpret_cast<char*>(&length), 8);
  std::string header(length, ' ');
  in.read(header.data(), static_cast<std::streamsize>(length));
  std::string meta = nlohmann::json::parse(header)["__metadata__"]["matlas"].get<std::string>();
  meta.pop_back();  // the closing brace
  return meta + ",\"deep\":" + std::string(static_cast<std::size_t>(depth), '[') +
         std::string(static_cast<std::size_t>(depth), ']') + "}";
}

TEST_F(CliOutputs, MetadataNestedTooDeepIsRefusedOnOpen) {
  test::TempDir t;
  const fs::path crafted = t.path() / "crafted.matlas";
  fs::copy_file(model(), crafted);
  // 63 arrays inside the top-level object: 64 levels, the limit, still opens.
  test::replace_model_metadata_text(crafted, nested_metadata(model(), 63));
  EXPECT_NO_THROW(Model::open(crafted));
  // 100,000 levels used to load, then overflow the stack where the model is fingerprinted
  // (basis of a GI scene, serve).
  test::replace_model_metadata_text(crafted, nested_metadata(model(), 100000));
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"latent", crafted.string()},
        std::vector<std::string>{"basis", crafted.string(), "--scene", "box", "--width", "4", "--height", "3",
                                 "--spp", "1", "-o", (t.path() / "b.safetensors").string()}}) {
    const OutputsRun r = run_matlas(args);
    EXPECT_EQ(r.code, 1) << args[0] << ": " << r.out;
    EXPECT_CONTAINS(r.out, crafted.string() + ": corrupted model metadata: JSON nested more than 64 levels deep");
  }
}

TEST_F(CliOutputs, APermutedGridIsRefusedOnOpenAndNeverBuilt) {
  test::TempDir t;
  const fs::path crafted = t.path() / "crafted.matlas";
  for (const auto& grid : {std::vector<int>{16, 8, 8}, std::vector<int>{8, 16, 8}}) {
    fs::copy_file(model(), crafted, fs::copy_options::overwrite_existing);
    test::edit_model_metadata(crafted, [&](nlohmann::json& meta) { meta["grid"] = grid; });
    const OutputsRun r = run_matlas({"latent", crafted.string()});
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_CONTAINS(r.out, "crafted.matlas: corrupted model metadata: 'grid' [" + std::to_string(grid[0]) + ", " +
                               std::to_string(grid[1]) + ", " + std::to_string(grid[2]) +
                               "] is not [theta_h, theta_d, phi_d] with phi_d = 2 theta_d");
  }
  // A database on a grid a model cannot state is refused by the build (never a file that no
  // reader opens).
  write_database(t.path() / "db", random_catalog(4, 7), null_progress(), MerlDims{8, 8, 12});
  const fs::path out = t.path() / "m.matlas";
  const OutputsRun r = run_matlas({"build", (t.path() / "db").string(), "-o", out.string(), "--quiet"});
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_CONTAINS(r.out, "a model needs phi_d = 2 theta_d");
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace matlas
