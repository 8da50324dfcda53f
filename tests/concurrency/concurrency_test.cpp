// Many threads sampling one shared table of each kind (Cascade, EnvironmentLight,
// LocalEnvironmentTable, TabulatedBrdfSampler): every thread's results must equal the
// single-threaded ones bit for bit, which holds only if sample() / pdf() / eval() are truly const
// (no hidden state; the local table's lazily built slices are once-only and synchronised).
// `make test-tsan` runs these under ThreadSanitizer (label "concurrency"), which also reports any
// data race the equality check might miss. Plain std::threads, so TSan sees every synchronisation;
// the tables are built with TBB limited to the calling thread (SerialBuild), because libtbb is not
// instrumented: TSan cannot see its scheduler's synchronisation and reports its reused task
// objects as races (false positives, no suppression file needed this way). That the parallel
// build does not depend on the thread count is tested with the builders themselves.

#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <latch>
#include <memory>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/merl.h"
#include "acdf/brdf/tabulated_brdf_sampler.h"
#include "acdf/envmap/environment_light.h"
#include "acdf/envmap/local_environment_table.h"
#include "acdf/sampling/cascade.h"
#include "acdf/sampling/rng.h"

namespace {

using namespace acdf;

constexpr int kThreads = 8;

// In scope while a table is built: TBB runs its parallel loops on the calling thread only.
struct SerialBuild {
  tbb::global_control control{tbb::global_control::max_allowed_parallelism, 1};
};
#ifdef ACDF_SANITIZED_BUILD
constexpr uint32_t kQueries = 2'000;
#else
constexpr uint32_t kQueries = 20'000;
#endif

// The results of query i (any doubles describing it), computed on one thread, then by kThreads
// threads at once over the same shared object, each thread walking the queries from a different
// start so they hit the table in different orders.
void expectSameOnEveryThread(const std::function<std::vector<double>(uint32_t)>& query) {
  std::vector<std::vector<double>> reference(kQueries);
  for (uint32_t i = 0; i < kQueries; ++i) reference[i] = query(i);
  std::vector<uint32_t> mismatches(kThreads, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (uint32_t k = 0; k < kQueries; ++k) {
        const uint32_t i = (k + static_cast<uint32_t>(t) * (kQueries / kThreads)) % kQueries;
        if (query(i) != reference[i]) ++mismatches[t];
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (int t = 0; t < kThreads; ++t) EXPECT_EQ(mismatches[t], 0u) << "thread " << t;
}

// Three variates for query i, reproducible from i alone.
std::array<float, 3> variates(uint32_t i) {
  Pcg32 rng(i);
  return {rng.nextFloat(), rng.nextFloat(), rng.nextFloat()};
}

TEST(SharedTables, Cascade) {
  // 16 conditioning slices × 64 × 32 sampled cells, adaptive, with a peaked function.
  const std::vector<GridAxis> axes = {GridAxis(16), GridAxis(64), GridAxis(32)};
  std::vector<float> values(16 * 64 * 32);
  Pcg32 rng(11);
  for (float& v : values) v = rng.nextFloat() < 0.2f ? 100.0f * rng.nextFloat() : rng.nextFloat();
  CascadeOptions options;
  options.conditioningDims = 1;
  const Cascade cascade = [&] {
    SerialBuild serial;
    return Cascade(values, axes, options);
  }();
  expectSameOnEveryThread([&](uint32_t i) {
    const auto u = variates(i);
    const float condition[] = {u[2]};
    const SampleND s = cascade.sample(condition, std::span<const float>(u.data(), 2));
    float back[2];
    cascade.invert(condition, s.point(), back);
    return std::vector<double>{s.x[0], s.x[1], s.pdf, cascade.pdf(condition, s.point()), back[0], back[1]};
  });
}

TEST(SharedTables, EnvironmentLight) {
  const uint32_t width = 64, height = 32;
  std::vector<float> rgb(3 * width * height);
  Pcg32 rng(5);
  for (float& v : rgb) v = rng.nextFloat() < 0.05f ? 50.0f : rng.nextFloat();
  const auto map = std::make_shared<const EnvironmentMap>(width, height, std::move(rgb));
  for (auto strategy : {EnvironmentSampling::Uniform, EnvironmentSampling::Alias, EnvironmentSampling::Adaptive,
                        EnvironmentSampling::Compensated}) {
    SCOPED_TRACE(std::string(toString(strategy)));
    const EnvironmentLight light = [&] {
      SerialBuild serial;
      return EnvironmentLight(map, {.strategy = strategy});
    }();
    expectSameOnEveryThread([&](uint32_t i) {
      const auto u = variates(i);
      // Either kind of call (a compensated light answers them from different tables).
      const LightSampleContext context{.allowIncompletePdf = u[2] < 0.5f};
      const LightSample s = light.sample(context, u[0], u[1]);
      const Rgb l = light.eval(s.direction);
      return std::vector<double>{
          s.direction.x, s.direction.y, s.direction.z, s.pdf, light.pdf(context, s.direction), l.r};
    });
  }
}

// Lazy slice builds: kThreads threads, released at once, sample one fresh local table in the same
// order, so they all ask for each slice's first build together (one-pixel blocks make each build
// slow enough to overlap); every result must equal that of a table queried on one thread, and
// each slice is built once.
TEST(SharedTables, LocalEnvironmentTableLazyBuild) {
  SerialBuild serial;  // the slices are built by the std::threads, TBB inside each runs serially
  const uint32_t width = 64, height = 32;
  std::vector<float> rgb(3 * width * height);
  Pcg32 rng(9);
  for (float& v : rgb) v = rng.nextFloat() < 0.05f ? 50.0f : rng.nextFloat();
  const auto map = std::make_shared<const EnvironmentMap>(width, height, std::move(rgb));
  const LocalEnvironmentOptions options{.normalRows = 4, .normalColumns = 4, .blockSize = 1};
  auto query = [](const LocalEnvironmentTable& table, uint32_t i) {
    const auto u = variates(i);
    const Vec3d n = sampleUniformSphere(static_cast<float>(i % 7) / 7.0f, static_cast<float>(i % 5) / 5.0f);
    const LocalEnvironmentTable::Sample s = table.sample(n, u[0], u[1]);
    return std::vector<double>{s.direction.x, s.direction.y, s.direction.z, s.pdf, table.pdf(n, s.direction)};
  };
  const LocalEnvironmentTable reference(map, options);
  std::vector<std::vector<double>> expected(kQueries);
  for (uint32_t i = 0; i < kQueries; ++i) expected[i] = query(reference, i);

  const LocalEnvironmentTable shared(map, options);
  std::vector<uint32_t> mismatches(kThreads, 0);
  std::latch start(kThreads);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      start.arrive_and_wait();
      for (uint32_t i = 0; i < kQueries; ++i)
        if (query(shared, i) != expected[i]) ++mismatches[t];
      shared.bytes();  // reads the built slices while others may still be building
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (int t = 0; t < kThreads; ++t) EXPECT_EQ(mismatches[t], 0u) << "thread " << t;
  EXPECT_EQ(shared.slicesBuilt(), reference.slicesBuilt());
  EXPECT_EQ(shared.bytes(), reference.bytes());
}

TEST(SharedTables, TabulatedBrdfSampler) {
  SerialBuild serial;  // until the sampler is built
  const std::vector<double> table = AnalyticBrdf::preset(AnalyticBrdf::presetNames().front()).merlTable();
  const std::span<const double> all(table);
  const auto brdf = std::make_shared<const MerlBrdf>(all.subspan(0, MerlBrdf::kCells),
                                                     all.subspan(MerlBrdf::kCells, MerlBrdf::kCells),
                                                     all.subspan(2 * MerlBrdf::kCells, MerlBrdf::kCells));
  TabulatedBrdfOptions options;
  options.thetaOutCells = 8;
  options.phiOutCells = 4;
  options.thetaHalfCells = 32;
  options.phiHalfCells = 16;
  options.supersampling = 1;
  const TabulatedBrdfSampler sampler(brdf, options);
  expectSameOnEveryThread([&](uint32_t i) {
    const auto u = variates(i);
    const Vec3d wo = sphericalDirection(std::acos(0.05 + 0.9 * u[2]), 6.283185307179586 * u[0]);
    const BrdfSample s = sampler.sample(wo, u[1], u[2]);
    return std::vector<double>{s.wi.x, s.wi.y, s.wi.z, s.pdf, s.weight.r, sampler.pdf(wo, s.wi)};
  });
}

}  // namespace
