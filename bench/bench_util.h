#pragma once
// Helpers shared by the bench_* programs: pre-generated variates, peak-memory probes and an
// interleaved head-to-head timer for ratios that survive a noisy machine.

#include <malloc.h>
#include <sys/resource.h>

#include <benchmark/benchmark.h>
#include <algorithm>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "acdf/sampling/rng.h"

namespace acdf::bench {

// Buffers of pre-generated variates are this long (a power of two, cycled with a mask), so the
// RNG is not part of a timed sample() call. 64K floats per dimension stay in L2.
inline constexpr std::size_t kVariates = std::size_t{1} << 16;
inline constexpr std::size_t kVariateMask = kVariates - 1;

inline std::vector<float> variates(std::size_t count, uint64_t seed) {
  Pcg32 rng(seed);
  std::vector<float> u(count);
  for (float& v : u) v = rng.nextFloat();
  return u;
}

// A field of /proc/self/status in kB ("VmRSS", "VmHWM"); -1 if unavailable.
inline long procStatusKb(const char* key) {
  std::ifstream status("/proc/self/status");
  std::string line;
  const std::string prefix = std::string(key) + ":";
  while (std::getline(status, line))
    if (line.rfind(prefix, 0) == 0) return std::stol(line.substr(prefix.size()));
  return -1;
}

// Peak resident memory added by the code between start() and stop(), process-wide (so TBB's
// worker threads count). start() returns freed heap memory to the OS and resets the kernel's
// high-water mark (writing 5 to /proc/self/clear_refs, Linux >= 4.0); stop() reads it back.
// Returns -1 when the high-water mark cannot be reset.
class PeakMemory {
 public:
  void start() {
    malloc_trim(0);
    std::ofstream clear("/proc/self/clear_refs");
    clear << "5";
    clear.flush();
    ok_ = static_cast<bool>(clear);
    baseKb_ = procStatusKb("VmRSS");
  }
  double stopBytes() const {
    long hwm = procStatusKb("VmHWM");
    if (!ok_ || hwm < 0 || baseKb_ < 0) return -1;
    return 1024.0 * static_cast<double>(std::max(0L, hwm - baseKb_));
  }

 private:
  bool ok_ = false;
  long baseKb_ = -1;
};

// CPU time (user + system) used so far by every thread of the process, in seconds. On a shared
// machine, wall time depends on what else runs; this is the work a build did.
inline double processCpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  auto sec = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  return sec(u.ru_utime) + sec(u.ru_stime);
}

inline double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// Runs each contender on a chunk of `ops` operations in turn, round after round, and keeps the
// per-chunk ns/op: interleaving exposes all contenders to the same machine noise, so the ratio
// of their medians is far steadier than a ratio of two separately run benchmarks.
// contender(offset) performs `ops` operations starting at variate offset `offset`.
class HeadToHead {
 public:
  using Contender = std::function<void(std::size_t offset)>;
  explicit HeadToHead(std::size_t opsPerChunk) : ops_(opsPerChunk) {}

  void add(Contender c) {
    contenders_.push_back(std::move(c));
    nsPerOp_.emplace_back();
  }

  void round(std::size_t offset) {
    // Rotate the starting contender so none always runs first after the loop overhead.
    std::size_t n = contenders_.size();
    for (std::size_t k = 0; k < n; ++k) {
      std::size_t i = (k + rounds_) % n;
      auto t0 = std::chrono::steady_clock::now();
      contenders_[i](offset);
      auto t1 = std::chrono::steady_clock::now();
      nsPerOp_[i].push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / static_cast<double>(ops_));
    }
    ++rounds_;
  }

  double medianNsPerOp(std::size_t i) const { return median(nsPerOp_[i]); }

  // For contenders added as sample(uniform, alias, adaptive) then pdf(uniform, alias, adaptive):
  // the median ns/op of each and the alias and adaptive ratios to uniform, as counters.
  void reportSamplersVsUniform(benchmark::State& st) const { reportVsUniform(st, {"uniform", "alias", "adaptive"}); }

  // The same for any samplers, `names` in the order added, "uniform" first (the reference).
  void reportVsUniform(benchmark::State& st, const std::vector<std::string>& names) const {
    const char* what[] = {"sample", "pdf"};
    for (std::size_t k = 0; k < 2; ++k) {
      const std::string p = what[k];
      const double uni = medianNsPerOp(names.size() * k);
      for (std::size_t i = 0; i < names.size(); ++i) {
        const double ns = medianNsPerOp(names.size() * k + i);
        st.counters[p + "_ns_" + names[i]] = ns;
        if (i > 0) st.counters[p + "_" + names[i] + "_vs_uniform"] = ns / uni;
      }
    }
  }

 private:
  std::size_t ops_;
  std::size_t rounds_ = 0;
  std::vector<Contender> contenders_;
  std::vector<std::vector<double>> nsPerOp_;
};

}  // namespace acdf::bench
