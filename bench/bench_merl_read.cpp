// Reading one MERL file (35 MB) with read_merl against the floor: the same bytes read raw from the
// page cache with read() into a preallocated, already touched buffer. The ratio (target <= 1.3)
// is measured in one benchmark that alternates the two in every iteration; it is reported for wall
// time (`ratio`) and for the thread's CPU time (`cpu_ratio`, system time included), which stays
// meaningful when other processes load the machine. read_merl reads into huge-page storage left
// uninitialised, in 1 MiB chunks each checked for NaN/Inf while in cache (docs/ANALYTIC.md).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fcntl.h>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <sys/mman.h>
#include <unistd.h>
#include <vector>

#include "brdf/analytic.h"
#include "brdf/tabulate.h"
#include "formats/merl_file.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
constexpr std::size_t kHeader = matlas::MerlFile::kHeaderBytes;

/// A 90x90x180 MERL file of a GGX gold, written once into a private temporary folder (removed at
/// exit) and read once so that it sits in the page cache; plus the raw read's destination buffer,
/// allocated and touched once.
class BenchFile {
public:
  BenchFile() {
    std::string templ = (fs::temp_directory_path() / "matlas-bench-XXXXXX").string();
    if (!::mkdtemp(templ.data())) throw std::runtime_error("mkdtemp failed");
    dir_ = templ;
    path_ = dir_ / "ggx-gold-a0.20.binary";
    matlas::write_merl(path_, matlas::tabulate(matlas::GgxConductor{matlas::Rgb(1.0, 0.782, 0.344), 0.2}));
    bytes_ = fs::file_size(path_);
    buffer_.reset(new char[bytes_]);
    std::memset(buffer_.get(), 0, bytes_);
    read_raw(buffer_.get());
  }
  ~BenchFile() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  const fs::path& path() const { return path_; }
  std::size_t bytes() const { return bytes_; }
  std::size_t values() const { return (bytes_ - kHeader) / sizeof(double); }
  char* buffer() const { return buffer_.get(); }

  /// The floor: open + read() of the whole file + close.
  void read_raw(char* out) const {
    const int fd = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error("open failed");
    std::size_t done = 0;
    while (done < bytes_) {
      const ssize_t got = ::read(fd, out + done, bytes_ - done);
      if (got <= 0) break;
      done += static_cast<std::size_t>(got);
    }
    ::close(fd);
    if (done != bytes_) throw std::runtime_error("short read");
  }

private:
  fs::path dir_, path_;
  std::size_t bytes_ = 0;
  std::unique_ptr<char[]> buffer_;
};

const BenchFile& bench_file() {
  static const BenchFile file;
  return file;
}

double thread_cpu_seconds() {
  timespec ts{};
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

void set_bytes(benchmark::State& state) {
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bench_file().bytes()));
}

/// Alternates the raw read and `read` in every iteration; reports `read`'s wall time and the
/// ratios to the raw read.
template <class Read>
void versus_raw(benchmark::State& state, Read read) {
  const BenchFile& file = bench_file();
  double raw = 0, wall = 0, raw_cpu = 0, cpu = 0;
  for (auto _ : state) {
    auto t0 = Clock::now();
    double c0 = thread_cpu_seconds();
    file.read_raw(file.buffer());
    benchmark::ClobberMemory();
    raw += std::chrono::duration<double>(Clock::now() - t0).count();
    raw_cpu += thread_cpu_seconds() - c0;
    t0 = Clock::now();
    c0 = thread_cpu_seconds();
    read();
    const double w = std::chrono::duration<double>(Clock::now() - t0).count();
    cpu += thread_cpu_seconds() - c0;
    wall += w;
    state.SetIterationTime(w);
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["raw_ms"] = 1e3 * raw / n;
  state.counters["ratio"] = wall / raw;
  state.counters["raw_cpu_ms"] = 1e3 * raw_cpu / n;
  state.counters["cpu_ms"] = 1e3 * cpu / n;
  state.counters["cpu_ratio"] = cpu / raw_cpu;
  set_bytes(state);
}

void BM_ReadMerlVsRaw(benchmark::State& state) {
  const BenchFile& file = bench_file();
  versus_raw(state, [&] {
    matlas::BrdfTable table = matlas::read_merl(file.path());
    benchmark::DoNotOptimize(table.stored().data());
  });
}
BENCHMARK(BM_ReadMerlVsRaw)->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
