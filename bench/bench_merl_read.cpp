// Reading one MERL file (35 MB) with read_merl against the floor: the same bytes read raw from the
// page cache with read() into a preallocated, already touched buffer. The ratio (target <= 1.3)
// is measured in one benchmark that alternates the two in every iteration; it is reported for wall
// time (`ratio`) and for the thread's CPU time (`cpu_ratio`, system time included), which stays
// meaningful when other processes load the machine. The other cases break read_merl's cost down
// (fresh pages, zero-filling, the 12-byte shift of the values, the finite check) and measure a
// proposed read path that removes most of it (see docs/ANALYTIC.md, "Reading speed").
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

// --- A proposed read path (what src/formats/merl_file.cpp and BrdfTable could do) ----------------

/// True when no value is NaN or infinite (std::isfinite, as read_values; a branch-free OR over
/// the exponent bits was measured too and is no faster: the check is memory-bound).
bool all_finite(const double* v, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

/// pread straight into the table in 1 MiB chunks, each checked right after it arrives, while it
/// is still in the cache (read_values checks in a second pass over 35 MB, which no longer fits).
/// (A 4 KiB-aligned bounce buffer, to avoid the kernel's copy with a 12-byte misalignment, was
/// measured too: no faster once the destination is in huge pages.)
void proposed_read(const fs::path& path, double* out, std::size_t count) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("open failed");
  constexpr std::size_t kChunk = (1u << 20) / sizeof(double);
  for (std::size_t first = 0; first < count; first += kChunk) {
    const std::size_t n = std::min(kChunk, count - first);
    char* dst = reinterpret_cast<char*>(out + first);
    for (std::size_t done = 0; done < n * sizeof(double);) {
      const ssize_t got = ::pread(fd, dst + done, n * sizeof(double) - done,
                                  static_cast<off_t>(kHeader + first * sizeof(double) + done));
      if (got <= 0) {
        ::close(fd);
        throw std::runtime_error("short read");
      }
      done += static_cast<std::size_t>(got);
    }
    if (!all_finite(out + first, n)) {
      ::close(fd);
      throw std::runtime_error("non-finite value");
    }
  }
  ::close(fd);
}

/// Storage for a table: 2 MiB-aligned, advised for transparent huge pages (17 page faults for a
/// MERL table instead of about 8,600), and not zero-filled.
struct HugeBuffer {
  static constexpr std::size_t kHuge = 2u << 20;
  explicit HugeBuffer(std::size_t count)
      : bytes((count * sizeof(double) + kHuge - 1) / kHuge * kHuge),
        data(static_cast<double*>(std::aligned_alloc(kHuge, bytes))) {
    ::madvise(data, bytes, MADV_HUGEPAGE);
  }
  ~HugeBuffer() { std::free(data); }
  HugeBuffer(const HugeBuffer&) = delete;
  HugeBuffer& operator=(const HugeBuffer&) = delete;
  std::size_t bytes;
  double* data;
};

// --- The comparisons ---------------------------------------------------------------------------

void BM_ReadMerlVsRaw(benchmark::State& state) {
  const BenchFile& file = bench_file();
  versus_raw(state, [&] {
    matlas::BrdfTable table = matlas::read_merl(file.path());
    benchmark::DoNotOptimize(table.stored().data());
  });
}
BENCHMARK(BM_ReadMerlVsRaw)->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(2.0);

/// The proposed path into fresh storage, as a new BrdfTable would get it.
void BM_ProposedFreshVsRaw(benchmark::State& state) {
  const BenchFile& file = bench_file();
  versus_raw(state, [&] {
    HugeBuffer table(file.values());
    proposed_read(file.path(), table.data, file.values());
    benchmark::DoNotOptimize(table.data);
  });
}
BENCHMARK(BM_ProposedFreshVsRaw)->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(2.0);

/// The proposed path into reused storage (a `read_merl(path, BrdfTable& reuse)` in a streaming loop).
void BM_ProposedReusedVsRaw(benchmark::State& state) {
  const BenchFile& file = bench_file();
  HugeBuffer table(file.values());
  std::memset(table.data, 0, table.bytes);
  versus_raw(state, [&] {
    proposed_read(file.path(), table.data, file.values());
    benchmark::ClobberMemory();
  });
}
BENCHMARK(BM_ProposedReusedVsRaw)->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(2.0);

// --- Where read_merl's time goes (each one step away from the floor) ----------------------------

/// The floor alone.
void BM_Step0_RawReadPreallocated(benchmark::State& state) {
  const BenchFile& file = bench_file();
  for (auto _ : state) {
    file.read_raw(file.buffer());
    benchmark::ClobberMemory();
  }
  set_bytes(state);
}
BENCHMARK(BM_Step0_RawReadPreallocated)->Unit(benchmark::kMillisecond);

/// pread of the values only (file offset 12) into the preallocated buffer: misaligned kernel copy.
void BM_Step1_PreadValuesAtOffset12(benchmark::State& state) {
  const BenchFile& file = bench_file();
  const std::size_t bytes = file.bytes() - kHeader;
  for (auto _ : state) {
    const int fd = ::open(file.path().c_str(), O_RDONLY | O_CLOEXEC);
    for (std::size_t done = 0; done < bytes;) {
      const ssize_t got = ::pread(fd, file.buffer() + done, bytes - done, static_cast<off_t>(kHeader + done));
      if (got <= 0) break;
      done += static_cast<std::size_t>(got);
    }
    ::close(fd);
    benchmark::ClobberMemory();
  }
  set_bytes(state);
}
BENCHMARK(BM_Step1_PreadValuesAtOffset12)->Unit(benchmark::kMillisecond);

/// MerlFile::read_values (pread at offset 12 + a second pass of std::isfinite) into the
/// preallocated buffer: read_merl without the allocation.
void BM_Step2_ReadValuesPreallocated(benchmark::State& state) {
  const BenchFile& file = bench_file();
  std::vector<double> values(file.values(), 0.0);
  for (auto _ : state) {
    matlas::MerlFile merl(file.path());
    merl.read_values(0, values.size(), values.data());
    benchmark::ClobberMemory();
  }
  set_bytes(state);
}
BENCHMARK(BM_Step2_ReadValuesPreallocated)->Unit(benchmark::kMillisecond);

/// Raw read into a fresh, untouched allocation (4 KiB page faults, no zero-filling).
void BM_Step3_RawReadFreshBuffer(benchmark::State& state) {
  const BenchFile& file = bench_file();
  for (auto _ : state) {
    std::unique_ptr<char[]> fresh(new char[file.bytes()]);
    file.read_raw(fresh.get());
    benchmark::DoNotOptimize(fresh.get());
  }
  set_bytes(state);
}
BENCHMARK(BM_Step3_RawReadFreshBuffer)->Unit(benchmark::kMillisecond);

/// Raw read into a fresh zero-filled vector (what BrdfTable's constructor allocates).
void BM_Step4_RawReadZeroedVector(benchmark::State& state) {
  const BenchFile& file = bench_file();
  for (auto _ : state) {
    std::vector<double> v(file.bytes() / sizeof(double) + 1, 0.0);
    file.read_raw(reinterpret_cast<char*>(v.data()));
    benchmark::DoNotOptimize(v.data());
  }
  set_bytes(state);
}
BENCHMARK(BM_Step4_RawReadZeroedVector)->Unit(benchmark::kMillisecond);

/// The std::isfinite pass alone over 35 MB, as read_values does it (a throw inside the loop).
void BM_FiniteCheckIsfinite(benchmark::State& state) {
  const BenchFile& file = bench_file();
  std::vector<double> values(file.values());
  std::memcpy(values.data(), file.buffer() + kHeader, values.size() * sizeof(double));
  for (auto _ : state) {
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!std::isfinite(values[i])) throw std::runtime_error("non-finite value at " + std::to_string(i));
    benchmark::ClobberMemory();
  }
  set_bytes(state);
}
BENCHMARK(BM_FiniteCheckIsfinite)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
