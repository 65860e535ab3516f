// The commands that split their work across MPI ranks (issue 31), run by `mpirun -np 2` against
// one process on generated data: `build` (data, mean, mask, Gram matrices and latent points
// bitwise; albedo curves to rounding), `evaluate` (the report's figures), `zonal` and `basis`
// (the same coefficients and pixels); a bad file read by one rank only fails both ranks with the
// file's name, no hang and no file left behind. Skipped where CMake found no MPI.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "core/communicator.h"
#include "formats/merl_file.h"
#include "formats/safetensors.h"
#include "formats/synth_database.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

namespace fs = std::filesystem;

#ifdef MATLAS_MPIEXEC
constexpr bool kHaveMpi = true;
constexpr const char* kMpiexec = MATLAS_MPIEXEC;
#else
constexpr bool kHaveMpi = false;
constexpr const char* kMpiexec = "";
#endif

/// Small grid (16 x 16 x 32: 24576 values per file) in blocks of 512 columns: 48 blocks, 24 per rank.
constexpr MerlDims kDims{16, 16, 32};
constexpr std::size_t kBlockColumns = 512;
constexpr std::size_t kValues = 3 * 16 * 16 * 32;

struct Result {
  int code = -1;
  std::string out;
};

/// Runs `PROGRAM ARGS...` with a time limit (a hang fails the test instead of blocking it).
Result run_process(const std::string& program, const std::vector<std::string>& args, int seconds = 60) {
  test::TempDir tmp("matlas-mpi-out");
  const fs::path out = tmp.path() / "out.txt";
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    // CI runs as root, which Open MPI refuses unless told.
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    ::setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 1);
    std::vector<std::string> copy = args;
    std::string exe = program;
    std::vector<char*> argv{exe.data()};
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::alarm(static_cast<unsigned>(seconds));
    ::execv(exe.c_str(), argv.data());
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  std::ifstream in(out);
  r.out.assign(std::istreambuf_iterator<char>(in), {});
  return r;
}

Result matlas(const std::vector<std::string>& args) { return run_process(MATLAS_EXE, args); }

Result mpirun(int ranks, const std::vector<std::string>& args) {
  std::vector<std::string> all{"-np", std::to_string(ranks), "--oversubscribe", MATLAS_EXE};
  all.insert(all.end(), args.begin(), args.end());
  return run_process(kMpiexec, all, 90);
}

/// `matlas COMMAND INPUT -o SINGLE FLAGS...` in one process, then with `mpirun -np 2` into SPLIT;
/// both must succeed. Returns the two ranks' output.
Result single_and_split(const std::string& command, const fs::path& input, const std::vector<std::string>& flags,
                        const fs::path& single, const fs::path& split) {
  std::vector<std::string> args{command, input.string(), "-o", single.string()};
  args.insert(args.end(), flags.begin(), flags.end());
  const Result one = matlas(args);
  EXPECT_EQ(one.code, 0) << one.out;
  args[3] = split.string();
  Result two = mpirun(2, args);
  EXPECT_EQ(two.code, 0) << two.out;
  return two;
}

/// Overwrites value index v of a MERL file (the stored, unscaled double).
void poke_value(const fs::path& file, std::size_t v, double value) {
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(static_cast<std::streamoff>(MerlFile::kHeaderBytes + v * sizeof(double)));
  f.write(reinterpret_cast<const char*>(&value), sizeof value);
  ASSERT_TRUE(f.good()) << file;
}

std::vector<fs::path> files_of(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

/// max |a - b| over two tensors of doubles, and max |a|.
std::pair<double, double> difference(const SafetensorsFile& a, const SafetensorsFile& b, const std::string& name) {
  const auto x = a.view<double>(name, DType::F64), y = b.view<double>(name, DType::F64);
  EXPECT_EQ(x.size(), y.size()) << name;
  double d = 0, m = 0;
  for (std::size_t k = 0; k < std::min(x.size(), y.size()); ++k) {
    d = std::max(d, std::abs(x[k] - y[k]));
    m = std::max(m, std::abs(x[k]));
  }
  return {d, m};
}

bool same_bytes(const SafetensorsFile& a, const SafetensorsFile& b, const std::string& name) {
  const TensorInfo* x = a.find(name);
  const TensorInfo* y = b.find(name);
  return x && y && x->bytes() == y->bytes() && std::memcmp(a.bytes(*x), b.bytes(*y), x->bytes()) == 0;
}

class MpiBuild : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    if (!kHaveMpi) return;
    dir_ = new test::TempDir("matlas-mpi");
    const auto files = write_database(db(), random_catalog(12, 3), null_progress(), kDims);
    // Columns that one material lacks, in either rank's share: the shares keep different counts,
    // so rank 1's data starts where rank 0's kept columns end, not at half the file.
    for (const std::size_t v : {std::size_t{5}, std::size_t{600}, std::size_t{601}, std::size_t{7000},
                                std::size_t{13000}, std::size_t{20000}})
      poke_value(files[3], v, -1.0);
  }
  static void TearDownTestSuite() { delete dir_; }
  void SetUp() override {
    if (!kHaveMpi) GTEST_SKIP() << "built without MPI (Debian: libopenmpi-dev openmpi-bin)";
  }
  static fs::path db() { return dir_->path() / "db"; }
  static inline test::TempDir* dir_ = nullptr;
};

TEST_F(MpiBuild, TwoRanksWriteTheSingleProcessModel) {
  const fs::path single = dir_->path() / "single.matlas", split = dir_->path() / "split.matlas";
  const Result r =
      single_and_split("build", db(), {"--quiet", "--block-columns", std::to_string(kBlockColumns)}, single, split);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("ranks            2 (MPI), the pass split by column blocks"), std::string::npos) << r.out;
  EXPECT_EQ(std::count_if(fs::directory_iterator(dir_->path()), fs::directory_iterator{},
                          [](const fs::directory_entry& e) { return e.path().filename().string().find(".tmp-") !=
                                                                        std::string::npos ||
                                                                    e.path().filename().string().find(".rank-") !=
                                                                        std::string::npos; }),
            0);

  const SafetensorsFile a = SafetensorsFile::open(single), b = SafetensorsFile::open(split);
  // The data is not reduced: every rank writes its blocks' values as one process would.
  for (const char* name : {"data", "mean", "value_column"}) EXPECT_TRUE(same_bytes(a, b, name)) << name;
  EXPECT_EQ(a.find("data")->shape, b.find("data")->shape);
  EXPECT_EQ(static_cast<std::size_t>(a.find("data")->shape[0]), kValues - 6);  // the 6 dropped columns
  // The Grams are compensated sums (gram_update.h) that the ranks add up with compensation: the
  // single process's bits, and so the same latent placement, bit for bit.
  for (const char* name : {"gram", "layout_gram", "latent"}) EXPECT_TRUE(same_bytes(a, b, name)) << name;
  // The albedo curves are plain sums of the ranks' partial sums: the same to rounding.
  const auto [d, m] = difference(a, b, "albedo");
  std::cout << "albedo: max |single - mpi| " << d << " (" << d / m << " of the largest entry)\n";
  EXPECT_LE(d, 1e-13 * m);
  const std::string meta = b.metadata().at("matlas");
  EXPECT_NE(meta.find("\"distributed\""), std::string::npos);
  EXPECT_NE(meta.find("xxh3_64_of_parts"), std::string::npos);
}

TEST_F(MpiBuild, ABadFileInOneRanksShareFailsEveryRankNamingIt) {
  const fs::path bad = dir_->path() / "bad";
  fs::create_directories(bad);
  for (const fs::path& f : files_of(db())) fs::copy_file(f, bad / f.filename());
  const fs::path broken = files_of(bad)[5];
  poke_value(broken, 20000, std::numeric_limits<double>::quiet_NaN());  // in rank 1's share only
  const fs::path out = dir_->path() / "bad.matlas";
  const Result r = mpirun(2, {"build", bad.string(), "-o", out.string(), "--quiet", "--block-columns",
                              std::to_string(kBlockColumns)});
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find(broken.filename().string()), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("rank 1 of 2"), std::string::npos) << r.out;  // rank 0 tells whose failure it was
  EXPECT_FALSE(fs::exists(out));
  for (const auto& e : fs::directory_iterator(dir_->path()))
    EXPECT_EQ(e.path().filename().string().find("bad.matlas"), std::string::npos) << e.path();  // no temporaries
}

TEST_F(MpiBuild, OtherCommandsRefuseToRunOnSeveralRanks) {
  const Result r = mpirun(2, {"info", files_of(db())[0].string()});
  EXPECT_NE(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("only `matlas build`, `evaluate`, `zonal` and `basis` split their work across MPI ranks"),
            std::string::npos)
      << r.out;
}

/// The single-process model of the database (built once per test that needs one).
fs::path single_model(const fs::path& dir, const fs::path& db) {
  const fs::path model = dir / "zonal-basis.matlas";
  if (!fs::exists(model)) {
    const Result r = matlas({"build", db.string(), "-o", model.string(), "--quiet", "--dim", "2"});
    EXPECT_EQ(r.code, 0) << r.out;
  }
  return model;
}

/// max |a - b| and max |a| over two float32 tensors of the same shape.
std::pair<double, double> float_difference(const SafetensorsFile& a, const SafetensorsFile& b, const std::string& name) {
  const auto x = a.view<float>(name, DType::F32), y = b.view<float>(name, DType::F32);
  EXPECT_EQ(a.find(name)->shape, b.find(name)->shape) << name;
  double d = 0, m = 0;
  for (std::size_t k = 0; k < std::min(x.size(), y.size()); ++k) {
    d = std::max(d, std::abs(double{x[k]} - double{y[k]}));
    m = std::max(m, std::abs(double{x[k]}));
  }
  return {d, m};
}

// `mpirun -np 2 matlas zonal`: each rank projects its share of the tables (a folder's files, or a
// model's mean and materials); rank 0 writes the single process's file.
TEST_F(MpiBuild, ZonalOnTwoRanksWritesTheSingleProcessCoefficients) {
  const fs::path model = single_model(dir_->path(), db());
  for (const fs::path& input : {db(), model}) {
    const std::string stem = input == db() ? "zonal-db" : "zonal-model";
    const fs::path single = dir_->path() / (stem + "-1.safetensors"), split = dir_->path() / (stem + "-2.safetensors");
    const Result r = single_and_split("zonal", input, {"--bands", "8", "--theta-o", "8"}, single, split);
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("12 materials"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("2 MPI ranks"), std::string::npos) << r.out;
    const SafetensorsFile a = SafetensorsFile::open(single), b = SafetensorsFile::open(split);
    EXPECT_EQ(a.metadata().at("names"), b.metadata().at("names")) << stem;
    EXPECT_EQ(a.find("coefficients")->shape, b.find("coefficients")->shape) << stem;
    EXPECT_EQ(a.find("coefficients")->shape[0], 12) << stem;
    // A folder's tables are projected one by one, as one process does: the same bytes. A model's
    // share goes through the same blocked products on fewer columns: the same to rounding.
    if (input == db()) {
      EXPECT_TRUE(same_bytes(a, b, "coefficients"));
      EXPECT_EQ(b.find("mean"), nullptr);
    } else {
      for (const char* name : {"coefficients", "mean"}) {
        const auto [d, m] = float_difference(a, b, name);
        EXPECT_GT(m, 0.0) << name;
        EXPECT_LE(d, 1e-6 * m) << name;
      }
    }
  }
}

TEST_F(MpiBuild, ABadFileInOneRanksShareOfZonalFailsEveryRankNamingIt) {
  const fs::path bad = dir_->path() / "bad-zonal";
  fs::create_directories(bad);
  for (const fs::path& f : files_of(db())) fs::copy_file(f, bad / f.filename());
  const fs::path broken = files_of(bad)[8];  // rank 1 projects files 6..11
  poke_value(broken, 100, std::numeric_limits<double>::quiet_NaN());
  const fs::path out = dir_->path() / "bad-zonal.safetensors";
  const Result r = mpirun(2, {"zonal", bad.string(), "-o", out.string(), "--bands", "4", "--theta-o", "4"});
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find(broken.filename().string()), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("NaN"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("rank 1 of 2"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(out));
}

/// The numbers of a CSV file's rows (the header and text fields left out), row by row.
std::vector<std::vector<double>> csv_numbers(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);  // header
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double>& row = rows.emplace_back();
    std::stringstream fields(line);
    for (std::string field; std::getline(fields, field, ',');) {
      char* end = nullptr;
      const double v = std::strtod(field.c_str(), &end);
      if (!field.empty() && end == field.c_str() + field.size()) row.push_back(v);
    }
  }
  return rows;
}

// `mpirun -np 2 matlas evaluate`: the Gram passes and the distance pass read half of every file
// on each rank and add up their sums, the fits are shared out and exchanged; rank 0 writes the
// report. Its Grams are the single process's bits (compensated sums), so are its fits; the
// distances are sums of the ranks' sums, the same to rounding: every figure of the report agrees
// to the 9 digits it prints.
TEST_F(MpiBuild, EvaluateOnTwoRanksReportsTheSingleProcessStudy) {
  const fs::path single = dir_->path() / "evaluate-1", split = dir_->path() / "evaluate-2";
  const Result r = single_and_split("evaluate", db(),
                                    {"--no-checks", "--quiet", "--dims", "2,3", "--layouts", "cosine-linear,cbrt",
                                     "--materials", "4", "--pairs", "3"},
                                    single, split);
  ASSERT_EQ(r.code, 0) << r.out;
  ASSERT_TRUE(fs::exists(split / "report.json")) << r.out;
  for (const char* file : {"material_distances.csv", "configs.csv", "loo.csv", "paths.csv"}) {
    const auto a = csv_numbers(single / file), b = csv_numbers(split / file);
    ASSERT_EQ(a.size(), b.size()) << file;
    ASSERT_FALSE(a.empty()) << file;
    double worst = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a[i].size(), b[i].size()) << file << " row " << i;
      for (std::size_t k = 0; k < a[i].size(); ++k) {
        if (std::string(file) == "configs.csv" && k + 1 == a[i].size()) continue;  // the fits' seconds
        worst = std::max(worst, std::abs(a[i][k] - b[i][k]) / std::max(1.0, std::abs(a[i][k])));
      }
    }
    std::cout << file << ": largest difference " << worst << " (relative)\n";
    EXPECT_LE(worst, 1e-6) << file;
  }
}

// `mpirun -np 2 matlas basis`: the previews' image basis (every other row on each rank) and a GI
// basis (a share of the batches on each rank) are the single process's, pixel for pixel.
TEST_F(MpiBuild, BasisOnTwoRanksRendersTheSingleProcessImages) {
  const fs::path model = single_model(dir_->path(), db());
  struct Case {
    std::string stem;
    std::vector<std::string> flags;
    std::vector<std::string> tensors;
  };
  const std::vector<Case> cases{
      {"image-basis", {"--width", "24", "--height", "17", "--spp", "4", "--precision", "f32"}, {"mean", "images"}},
      {"gi-basis", {"--scene", "floor", "--width", "20", "--height", "15", "--spp", "2", "--batch", "4"},
       {"p", "linear", "full"}}};
  for (const Case& c : cases) {
    const fs::path single = dir_->path() / (c.stem + "-1.safetensors"), split = dir_->path() / (c.stem + "-2.safetensors");
    const Result r = single_and_split("basis", model, c.flags, single, split);
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("wrote " + split.string()), std::string::npos) << r.out;
    const SafetensorsFile a = SafetensorsFile::open(single), b = SafetensorsFile::open(split);
    for (const std::string& name : c.tensors) {
      EXPECT_TRUE(same_bytes(a, b, name)) << c.stem << " " << name;
      const auto [d, m] = float_difference(a, b, name);
      EXPECT_GT(m, 0.0) << c.stem << " " << name;  // not two black images
      EXPECT_EQ(d, 0.0) << c.stem << " " << name;
    }
  }
}

}  // namespace
}  // namespace matlas
