// The `matlas` command on hostile and careless input (issue 14): FIFOs, outputs that are inputs,
// interrupted builds, absurd values, malformed flags, crafted models. Each case checks the exit
// code (1 bad input, 2 usage) and that the message names the problem. Most cases call the command
// in-process (cli::run); those about the process itself (signals, a FIFO that must not block,
// `serve`, the exit status seen by a shell) run the built executable.
#include <chrono>
#include <algorithm>
#include <csignal>
#include <functional>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "brdf/catalog.h"
#include "cli/in_process.h"
#include "cli/model_surgery.h"
#include "core/atomic_file.h"
#include "formats/merl_file.h"
#include "formats/synth_database.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

namespace fs = std::filesystem;

struct CommandResult {
  int code = -1;
  std::string out;  ///< stdout and stderr
};

/// Runs `matlas ARGS...` in this process (standard error after standard output).
CommandResult run(const std::vector<std::string>& args) {
  const test::CliOutput r = test::call_matlas(args);
  return {r.code, r.out + r.err};
}

/// Runs the built `matlas ARGS...` as a child process with a time limit (a hang fails the test
/// instead of blocking it).
CommandResult run_process(const std::vector<std::string>& args, int seconds = 60) {
  test::TempDir tmp("matlas-cli-out");
  const fs::path out = tmp.path() / "out.txt";
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    std::vector<char*> argv;
    std::string exe = MATLAS_EXE;
    argv.push_back(exe.data());
    std::vector<std::string> copy = args;
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::alarm(static_cast<unsigned>(seconds));  // SIGALRM ends a hung command
    ::execv(exe.c_str(), argv.data());
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  CommandResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  std::ifstream in(out);
  r.out.assign(std::istreambuf_iterator<char>(in), {});
  return r;
}

#define EXPECT_CONTAINS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

class CliHardening : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("matlas-cli");
    write_database(dir_->path() / "db", random_catalog(5, 3), null_progress(), MerlDims{8, 8, 16});
    const CommandResult r = run({"build", (dir_->path() / "db").string(), "-o", model().string(), "--quiet"});
    ASSERT_EQ(r.code, 0) << r.out;
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path db() { return dir_->path() / "db"; }
  static fs::path model() { return dir_->path() / "m.matlas"; }
  static fs::path first_material() {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(db())) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files.front();
  }
  static inline test::TempDir* dir_ = nullptr;
};

// ---- 4. FIFOs are refused, never waited on
TEST_F(CliHardening, FifoInputsAreRefusedForEveryCommand) {
  test::TempDir t;
  const fs::path fifo = t.path() / "f.binary", fifo_model = t.path() / "f.matlas";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  ASSERT_EQ(::mkfifo(fifo_model.c_str(), 0644), 0);
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"info", fifo.string()},
           {"build", db().string(), fifo.string(), "-o", (t.path() / "x.matlas").string(), "--quiet"},
           {"project", model().string(), fifo.string()},
           {"latent", fifo_model.string()},
           {"serve", fifo_model.string(), "--port", "0"}}) {
    const CommandResult r = run_process(args, 20);
    EXPECT_EQ(r.code, 1) << args[0] << ": " << r.out;
    EXPECT_CONTAINS(r.out, "named pipe (FIFO)");
  }
}

// ---- The exit status a shell sees: 0 success, 1 bad input, 2 usage
TEST_F(CliHardening, ProcessExitStatusIsTheCommandsCode) {
  EXPECT_EQ(run_process({"--help"}).code, 0);
  CommandResult r = run_process({"latent", (dir_->path() / "absent.matlas").string()});
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_CONTAINS(r.out, "absent.matlas");
  r = run_process({"weights", model().string(), "--at", "0,0", "--top", "-1"});
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_CONTAINS(r.out, "--top");
}

// ---- `--cache` names the same folder for demo and serve (issue 15)
TEST_F(CliHardening, DemoAndServeShareTheCacheFolder) {
  test::TempDir t;
  const fs::path cache = t.path() / "cache";
  CommandResult r = run_process({"demo", "--no-serve", "--grid", "8,8,16", "--count", "4", "--size", "32", "--spp",
                                 "1", "--cache", cache.string()},
                                120);
  ASSERT_EQ(r.code, 0) << r.out;
  ASSERT_TRUE(fs::is_directory(cache / "bases")) << r.out;
  std::vector<fs::path> models;
  for (const auto& e : fs::directory_iterator(cache / "models")) models.push_back(e.path());
  ASSERT_EQ(models.size(), 1u);
  // serve with the same --cache finds the demo's image bases in cache/bases; it serves until
  // the time limit ends it (SIGALRM).
  r = run_process({"serve", models[0].string(), "--port", "0", "--size", "32", "--spp", "1", "--cache",
                   cache.string()},
                  5);
  EXPECT_CONTAINS(r.out, "cached in " + (cache / "bases").string());
  EXPECT_FALSE(fs::exists(cache / "cache")) << r.out;
}

// ---- 7. A build never overwrites one of its inputs
TEST_F(CliHardening, BuildRefusesAnOutputThatIsAnInput) {
  const fs::path input = first_material();
  const auto before = fs::file_size(input);
  CommandResult r = run({"build", db().string(), "-o", input.string(), "--quiet"});
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_CONTAINS(r.out, "is one of the inputs");
  test::TempDir t;
  const fs::path link = t.path() / "link.matlas";
  fs::create_symlink(fs::absolute(input), link);
  r = run({"build", db().string(), "-o", link.string(), "--quiet"});
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_CONTAINS(r.out, "is one of the inputs");
  EXPECT_EQ(fs::file_size(input), before);
  EXPECT_NO_THROW(read_merl(input));
}

// ---- 8. Temporary files: removed on SIGTERM/SIGINT, stale ones cleaned by the next run
TEST_F(CliHardening, StaleTemporaryFilesOfTheTargetAreRemoved) {
  test::TempDir t;
  const fs::path out = t.path() / "m.matlas";
  const fs::path stale = t.path() / "m.matlas.tmp-4194302";   // no such process (pid_max - 2)
  const fs::path other = t.path() / "n.matlas.tmp-4194302";   // another target: kept
  std::ofstream(stale) << "left by a killed build";
  std::ofstream(other) << "not ours";
  const CommandResult r = run({"build", db().string(), "-o", out.string(), "--quiet"});
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(other));
}

TEST_F(CliHardening, InterruptedBuildLeavesNoTemporaryFile) {
  test::TempDir t;
  // Big enough that the build is still writing when the signal comes.
  write_database(t.path() / "db", random_catalog(4, 5), null_progress(), MerlDims{90, 90, 180});
  for (const int sig : {SIGTERM, SIGINT}) {
    // On a loaded machine the build may finish between seeing its temporary file and the signal:
    // such a try proves nothing, so it is repeated (the build's output removed) until a signal
    // lands while the build runs.
    bool interrupted = false;
    for (int attempt = 0; attempt < 8 && !interrupted; ++attempt) {
      const fs::path out = t.path() / "m.matlas";
      fs::remove(out);
      const pid_t pid = ::fork();
      if (pid == 0) {
        const int null = ::open("/dev/null", O_WRONLY);
        ::dup2(null, 1);
        ::dup2(null, 2);
        ::execl(MATLAS_EXE, MATLAS_EXE, "build", (t.path() / "db").c_str(), "-o", out.c_str(), "--quiet",
                static_cast<char*>(nullptr));
        ::_exit(127);
      }
      const fs::path temp = out.string() + ".tmp-" + std::to_string(pid);
      const auto start = std::chrono::steady_clock::now();
      while (!fs::exists(temp) && !fs::exists(out) && std::chrono::steady_clock::now() - start < std::chrono::seconds(30))
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      ASSERT_TRUE(fs::exists(temp) || fs::exists(out)) << "the build never created its temporary file";
      ::kill(pid, sig);
      int status = 0;
      ::waitpid(pid, &status, 0);
      if (WIFEXITED(status) && WEXITSTATUS(status) == 0) continue;  // finished before the signal
      interrupted = true;
      EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << "status " << status;
      EXPECT_FALSE(fs::exists(temp)) << "signal " << sig;
      EXPECT_FALSE(fs::exists(out));
    }
    EXPECT_TRUE(interrupted) << "every build finished before signal " << sig << " reached it";
  }
}

// ---- 9. Absurd values and empty tables name the file and the problem
TEST_F(CliHardening, AbsurdAndNonFiniteValuesNameTheFile) {
  test::TempDir t;
  BrdfTable table = read_merl(first_material());
  table.stored()[5] = 1e300;
  write_file_atomic(t.path() / "huge.binary", encode_merl(table));  // write_merl refuses to write it
  CommandResult r = run({"info", (t.path() / "huge.binary").string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_CONTAINS(r.out, "huge.binary: absurd value 1e+300");
  r = run({"project", model().string(), (t.path() / "huge.binary").string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_CONTAINS(r.out, "huge.binary: absurd value");
  fs::copy(db(), t.path() / "db2");
  fs::copy_file(t.path() / "huge.binary", t.path() / "db2" / "huge.binary");
  r = run({"build", (t.path() / "db2").string(), "-o", (t.path() / "m.matlas").string(), "--quiet"});
  EXPECT_EQ(r.code, 1);
  EXPECT_CONTAINS(r.out, "huge.binary: absurd value");
}

TEST_F(CliHardening, ProjectingAnEmptyOrZeroTableFails) {
  test::TempDir t;
  BrdfTable table = read_merl(first_material());
  for (auto& v : table.stored()) v = 0.0;
  write_merl(t.path() / "zero.binary", table, true);
  for (auto& v : table.stored()) v = -1.0;
  write_merl(t.path() / "missing.binary", table, true);
  CommandResult r = run({"project", model().string(), (t.path() / "zero.binary").string()});
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_CONTAINS(r.out, "zero.binary: every measured value of the material is zero");
  r = run({"project", model().string(), (t.path() / "missing.binary").string()});
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_CONTAINS(r.out, "missing.binary: the material has no measured value");
}

// ---- 10. Flags: malformed points, non-finite numbers, negative counts, named in the message
TEST_F(CliHardening, MalformedFlagsAreRefusedNamingTheFlag) {
  const std::string m = model().string();
  CommandResult r = run({"weights", m, "--at", "0.05, "});
  EXPECT_EQ(r.code, 1);
  EXPECT_CONTAINS(r.out, "--at '0.05, ': coordinate 2 is empty");
  r = run({"weights", m, "--at", "0,0,"});
  EXPECT_EQ(r.code, 1);
  EXPECT_CONTAINS(r.out, "coordinate 3 is empty");
  r = run({"weights", m, "--at", "0,nan"});
  EXPECT_EQ(r.code, 1);
  EXPECT_CONTAINS(r.out, "not a finite number");
  r = run({"weights", m, "--at", "0,0", "--top", "-1"});
  EXPECT_EQ(r.code, 2);
  EXPECT_CONTAINS(r.out, "--top");
  r = run({"weights", m, "--at", "0,0", "--top", "4294967296"});
  EXPECT_EQ(r.code, 2);
  EXPECT_CONTAINS(r.out, "--top");
  r = run({"build", db().string(), "-o", "/tmp/never.matlas", "--starts", "-1"});
  EXPECT_EQ(r.code, 2);
  EXPECT_CONTAINS(r.out, "--starts");
  r = run({"render", m, "--material", "x", "-o", "/tmp/never.png", "--exposure", "nan"});
  EXPECT_EQ(r.code, 2);
  EXPECT_CONTAINS(r.out, "--exposure");
  EXPECT_FALSE(fs::exists("/tmp/never.png"));
}

// ---- 11. Unclear messages made clear
TEST_F(CliHardening, MessagesNameTheProblem) {
  const std::string m = model().string();
  const std::string name = first_material().stem().string();
  CommandResult r = run({"render", m, "--material", name, "-o", "/tmp/never.png", "--light", "nan,1,1", "--width", "8",
               "--height", "8", "--spp", "1", "--env", "constant"});
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_CONTAINS(r.out, "--light 'nan,1,1'");
  r = run({"render", m, "--material", name, "-o", "/tmp/never.png", "--sampler", "sobol", "--width", "8", "--height", "8",
           "--spp", "1", "--env", "constant"});
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_CONTAINS(r.out, "--sampler 'sobol': expected light-and-lobe, stratified or independent");
  r = run({"render", m, "--material", name, "-o", "/tmp/never.png", "--grazing-samples", "0.5", "--width", "8",
           "--height", "8", "--spp", "1", "--env", "constant"});
  EXPECT_NE(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "--grazing-samples");
  EXPECT_FALSE(fs::exists("/tmp/never.png"));
  r = run({"export", m, "--material", name, "-o", ""});
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_CONTAINS(r.out, "output file name is empty");
  EXPECT_EQ(r.out.find("internal error"), std::string::npos) << r.out;

  test::TempDir t;
  fs::copy(db(), t.path() / "db");
  fs::create_symlink("loop.binary", t.path() / "db" / "loop.binary");
  r = run({"build", (t.path() / "db").string(), "-o", (t.path() / "m.matlas").string(), "--quiet"});
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_CONTAINS(r.out, "loop.binary: too many levels of symbolic links");
  EXPECT_EQ(r.out.find("internal error"), std::string::npos) << r.out;
}

// ---- 2 and 11. Crafted models are refused with the file named
TEST_F(CliHardening, CraftedModelsAreRefused) {
  test::TempDir t;
  const fs::path crafted = t.path() / "crafted.matlas";
  struct Case {
    const char* what;
    std::function<void(nlohmann::json&)> edit;
  };
  const std::vector<Case> cases = {
      {"'grid' entries must be integers", [](nlohmann::json& m) { m["grid"] = {-8, -8, 16}; }},
      {"'grid' entries must be integers", [](nlohmann::json& m) { m["grid"] = {0, 0, 0}; }},
      {"missing or invalid 'kernel'", [](nlohmann::json& m) { m.erase("kernel"); }},
      {"version 1099511627776 is not supported", [](nlohmann::json& m) { m["format_version"] = 1ll << 40; }},
      {"'kernel.nugget' must be a finite positive number", [](nlohmann::json& m) { m["kernel"]["nugget"] = -1; }},
      {"latent tensor missing or of the wrong shape",
       [](nlohmann::json& m) { m["names"].push_back("ghost"); m["count"] = m["names"].size(); }},
  };
  for (const Case& c : cases) {
    fs::copy_file(model(), crafted, fs::copy_options::overwrite_existing);
    test::edit_model_metadata(crafted, c.edit);
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{"latent", crafted.string()},
          std::vector<std::string>{"serve", crafted.string(), "--port", "0", "--cache", t.path().string()}}) {
      const CommandResult r = args[0] == "serve" ? run_process(args, 20) : run(args);
      EXPECT_EQ(r.code, 1) << args[0] << ": " << r.out;
      EXPECT_CONTAINS(r.out, "crafted.matlas: ");
      EXPECT_CONTAINS(r.out, c.what);
    }
  }
}

TEST_F(CliHardening, AGiBasisResumesAndRenderRefusesWhatIsNotABasis) {
  test::TempDir tmp("matlas-cli-gi");
  const std::string basis = (tmp.path() / "b.safetensors").string();
  const std::vector<std::string> args = {"basis", model().string(), "--scene", "box", "--width", "8",
                                         "--height", "6", "--spp", "1", "--batch", "2", "-o", basis};
  const CommandResult first = run(args);
  ASSERT_EQ(first.code, 0) << first.out;
  EXPECT_TRUE(fs::exists(tmp.path() / "b.safetensors.cache" / "material-0005.safetensors"));
  const CommandResult again = run_process(args);  // progress messages go to the process's stderr
  ASSERT_EQ(again.code, 0) << again.out;
  EXPECT_CONTAINS(again.out, "reused 6 cached material images");
  // The former name still works, says it is deprecated, and reuses the same cache.
  std::vector<std::string> former = args;
  former[0] = "gi-basis";
  const CommandResult old = run_process(former);
  ASSERT_EQ(old.code, 0) << old.out;
  EXPECT_CONTAINS(old.out, "matlas gi-basis is deprecated");
  EXPECT_CONTAINS(old.out, "reused 6 cached material images");
  const CommandResult composed = run({"render", model().string(), "--at", "0,0", "--basis", basis, "-o",
                                      (tmp.path() / "x.exr").string()});
  EXPECT_EQ(composed.code, 0) << composed.out;
  EXPECT_TRUE(fs::exists(tmp.path() / "x.exr"));
  const CommandResult not_basis = run({"render", model().string(), "--at", "0,0", "--basis", model().string(), "-o",
                                       (tmp.path() / "y.exr").string()});
  EXPECT_EQ(not_basis.code, 1);
  EXPECT_CONTAINS(not_basis.out, "not a matlas basis");
  EXPECT_EQ(run({"basis", model().string(), "--scene", "box", "--spp", "0", "-o", basis}).code, 2);
  const CommandResult scene = run({"render", model().string(), "--at", "0,0", "--scene", "nope.txt", "-o",
                                   (tmp.path() / "z.png").string()});
  EXPECT_EQ(scene.code, 1);
  EXPECT_CONTAINS(scene.out, "nope.txt");
  // The previews' lighting options do not apply to a GI scene, which says its own.
  const CommandResult lit = run({"render", model().string(), "--at", "0,0", "--scene", "box", "--light", "0,1,0", "-o",
                                 (tmp.path() / "l.png").string()});
  EXPECT_EQ(lit.code, 1);
  EXPECT_CONTAINS(lit.out, "--light does not apply to a GI scene");
}

TEST_F(CliHardening, ServeRefusesABadGiBasisOrSize) {
  test::TempDir tmp("matlas-cli-gi-serve");
  const std::vector<std::string> common = {"serve", model().string(), "--port", "0", "--size", "32", "--spp", "1",
                                           "--cache", tmp.path().string()};
  std::vector<std::string> args = common;
  args.insert(args.end(), {"--gi-basis", model().string()});  // a model, not a GI basis
  CommandResult r = run_process(args, 60);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_CONTAINS(r.out, model().filename().string() + ": not a matlas GI basis");
  args = common;
  args.insert(args.end(), {"--gi-size", "3x3"});
  r = run_process(args, 60);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_CONTAINS(r.out, "--gi-size");
}

}  // namespace
}  // namespace matlas
