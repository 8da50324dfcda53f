#include "acdf/integrator/renderer.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "acdf/integrator/light_paths.h"
#include "acdf/integrator/path_integrator.h"
#include "acdf/integrator/sampler.h"
#include "parallel.h"

namespace acdf {

namespace {

struct Tile {
  uint32_t x0, y0, x1, y1;  // in film pixels
};

std::vector<Tile> makeTiles(const Film& film, uint32_t size) {
  std::vector<Tile> tiles;
  for (uint32_t y = 0; y < film.height(); y += size)
    for (uint32_t x = 0; x < film.width(); x += size)
      tiles.push_back({x, y, std::min(x + size, film.width()), std::min(y + size, film.height())});
  return tiles;
}

}  // namespace

uint32_t branchesThatPay(double raysBefore, double raysAfter, double varianceBefore, double varianceAfter) {
  if (!(raysAfter > 0) || !(varianceAfter > 0)) return 1;  // nothing after the first vertex to branch
  const double v0 = std::max(0.0, varianceBefore);
  const auto figure = [&](double k) { return (v0 + varianceAfter / k) * (raysBefore + k * raysAfter); };
  uint32_t best = 1;
  for (uint32_t k = 2; k <= kMaxAutoBranches; ++k)
    if (figure(k) < figure(best)) best = k;
  return figure(best) * kBranchingMargin <= figure(1) ? best : 1;
}

Film makeFilm(const Scene& scene) { return Film(scene.camera->crop().width(), scene.camera->crop().height()); }

namespace {

// What one pass renders and how.
struct PassPlan {
  uint32_t first = 0, last = 0;            // its samples of every pixel
  const GuidingField* lightField = nullptr;  // light sampled with (none: the light's own tables)
  const GuidingField* pathField = nullptr;   // paths continued with (none: the BSDF alone)
  // Guide, or connect, only the pixels with x + y even, and measure both halves.
  bool compare = false;
  bool recordLight = false;  // keep what its paths learn about the light
  bool recordPaths = false;  // and about the radiance they carry
  uint64_t recordStride = 1;  // of its pixel samples, keep every this many's records
  uint32_t branches = 1;      // paths per camera sample from the first vertex on
  bool connects = false;      // to light paths (light_paths.h)
};

// One pixel of a comparing pass: its samples' luminance mean and variance, and the rays they cast.
struct PixelSpread {
  double mean = 0, variance = 0;
  uint64_t rays = 0;
};

// A half of the pixels of a comparing pass: each pixel's variance relative to the squared mean of
// its 3 × 3 neighbourhood (both halves) plus the squared image mean, summed; and the rays and samples.
// A pixel's own mean would hide its fireflies (they raise it too), and the image mean alone
// would let the bright pixels' variance decide for all.
struct HalfStats {
  double relativeVariance = 0;
  uint64_t pixels = 0, rays = 0, samples = 0;

  // Relative variance per sample times rays per sample; 0 for a black half, which measures nothing.
  double cost() const {
    if (pixels == 0 || samples == 0) return 0;
    return relativeVariance / static_cast<double>(pixels) * (static_cast<double>(rays) / samples);
  }
};

// The halves of a comparing pass (pixels with x + y even in the full frame first) from its pixels'
// spreads, row-major over the film of `width` × `height` whose pixel (0, 0) is full-frame (x0, y0).
std::array<HalfStats, 2> compareHalves(const std::vector<PixelSpread>& pixels, uint32_t width, uint32_t height,
                                       uint32_t x0, uint32_t y0, uint32_t samplesPerPixel) {
  std::array<HalfStats, 2> halves{};
  double imageMean = 0;
  for (const PixelSpread& p : pixels) imageMean += p.mean;
  imageMean /= static_cast<double>(pixels.size());
  const double guard = imageMean * imageMean;
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      double around = 0;
      uint32_t count = 0;
      for (uint32_t ny = y > 0 ? y - 1 : 0; ny <= std::min(y + 1, height - 1); ++ny)
        for (uint32_t nx = x > 0 ? x - 1 : 0; nx <= std::min(x + 1, width - 1); ++nx, ++count)
          around += pixels[std::size_t{ny} * width + nx].mean;
      around /= count;
      const double scale = around * around + guard;
      if (!(scale > 0)) continue;  // black: measures nothing
      const PixelSpread& p = pixels[std::size_t{y} * width + x];
      HalfStats& half = halves[(x0 + x + y0 + y) % 2];
      half.relativeVariance += p.variance / scale;
      ++half.pixels;
      half.rays += p.rays;
      half.samples += samplesPerPixel;
    }
  return halves;
}

struct PassResult {
  std::vector<GuidingRecord> lightRecords, pathRecords;
  uint64_t recordedSamples = 0;
  std::array<HalfStats, 2> halves{};  // guided or connected, and not (a comparing pass)
  RayCounts rays;
};

// Records a pass may keep, about 100 MB: beyond it a pass keeps every k-th pixel sample's.
constexpr uint64_t kMaxRecordsPerPass = uint64_t{1} << 22;
// Fields learned from this many records are final: further passes that record and build cost time
// and lowered no variance (the room at 256 × 192, 64 spp: relative variance 0.531 from 1.3 M
// records, 0.532 from 2.6 M, 0.577 from 0.33 M).
constexpr std::size_t kEnoughRecords = std::size_t{1} << 20;

// Auto branching's measure: kProbeRows × kProbeColumns pixels spread over the full frame (not the
// crop, so every crop of a frame decides alike), each rendered with 1 and with kMeasuringBranches
// branches, each of these in two runs of kProbeSamples camera samples by samplers of the scene's
// kind with two fixed seeds (so every seed and sample count decides alike), none of them in the
// image. A pixel's value is a mean of samples whose points stratify each other, and Sobol points
// lower the variance of what comes before the first vertex's continuation (the pixel's position,
// the first hit: V0) and of the branches' light (V1) by amounts that differ by scene: on the
// spheres, whose caustic they hardly stratify, single samples (an earlier probe) measured
// V0 / V1 = 0.37, 8 samples measure 0.19, and 16 seeds of 64-spp renders give 0.02. Per pixel
// and branch count K, with m_A and m_B the two runs' mean luminances, n (m_A − m_B)² / 2 measures
// V0 + V1 / K as n samples leave them (the same pixel: no neighbour's difference of means in it);
// the two counts give V0 and V1. The runs of one seed share their camera samples, so the
// difference of the two measures holds little but the branches. In kSpreadGroups groups of probe
// rows, whose medians decide: a few fireflies decide a mean of squares, and with it the branch
// count, but only the group they fall in (and the medians of groups of fewer pixels with more
// samples each measure V1 too low: its fireflies fall in few).
constexpr uint32_t kMeasuringBranches = 4;
constexpr uint32_t kProbeSamples = 8;  // n
constexpr uint32_t kProbeRows = 24, kProbeColumns = 36;
constexpr std::size_t kSpreadGroups = 9;
constexpr std::array<uint64_t, 2> kProbeSeeds = {0x6272616e6368, 0x6272616e6369};

// Light paths per sample index (light_paths.h): one per kPixelsPerLightPath pixels of the full
// frame, at least kLeastLightPathsPerSample; the camera's paths of a sample index share them.
constexpr uint32_t kPixelsPerLightPath = 8;
constexpr uint32_t kLeastLightPathsPerSample = 1024;
// The samples of a pass with light paths (their pools are kept together), and of auto's comparing
// pass.
constexpr uint32_t kLightPathPassSamples = 8;
// What auto's comparing pass must measure to connect: behind the door ajar connections measure
// 0.90-0.92 (0.97x at equal time), in the room 1.37 (1.72x).
constexpr double kLightPathMargin = 1.1;

BranchingStats measureBranching(const Scene& scene, const PathIntegrator& integrator) {
  struct Group {
    double sum = 0;
    std::array<double, 2> runSquares{};  // one branch, kMeasuringBranches
    uint64_t samples = 0, pixels = 0;
  };
  const Camera& camera = *scene.camera;
  BranchingStats stats;
  std::array<std::unique_ptr<const Sampler>, 2> prototypes;
  for (std::size_t r = 0; r < 2; ++r)
    prototypes[r] = makeSampler(scene.settings.sampler, kProbeSeeds[r], camera.width());
  const uint32_t rows = std::min(kProbeRows, camera.height()), columns = std::min(kProbeColumns, camera.width());
  constexpr std::array<uint32_t, 2> kBranches = {1, kMeasuringBranches};
  // Each probe row on its own (in parallel), joined in row order: the same sums for any threads.
  struct Row {
    Group group;
    RayCounts rays;
  };
  std::vector<Row> probed(rows);
  forEachInParallel(rows, [&](std::size_t j) {
    Row& row = probed[j];
    const std::array<std::unique_ptr<Sampler>, 2> samplers = {prototypes[0]->clone(), prototypes[1]->clone()};
    const auto y = static_cast<uint32_t>((2 * j + 1) * camera.height() / (2 * rows));
    for (uint32_t i = 0; i < columns; ++i) {
      const auto x = static_cast<uint32_t>((2 * i + 1) * camera.width() / (2 * columns));
      for (std::size_t b = 0; b < 2; ++b) {
        std::array<double, 2> means{};
        for (std::size_t r = 0; r < 2; ++r) {
          Sampler& sampler = *samplers[r];
          double sum = 0;
          for (uint32_t k = 0; k < kProbeSamples; ++k) {
            sampler.startPixelSample(x, y, k);
            const auto [jx, jy] = sampler.getPixel2D();
            sum += integrator.radiance(camera.generateRay(x + jx, y + jy), sampler, row.rays, {}, kBranches[b])
                       .luminance();
          }
          means[r] = sum / kProbeSamples;
          row.group.sum += sum;
          row.group.samples += kProbeSamples;
        }
        const double difference = means[0] - means[1];
        row.group.runSquares[b] += kProbeSamples * 0.5 * difference * difference;
      }
      ++row.group.pixels;
    }
  });
  std::array<Group, kSpreadGroups> groups{};
  RayCounts rays;
  for (uint32_t j = 0; j < rows; ++j) {
    Group& group = groups[j % kSpreadGroups];
    const Row& row = probed[j];
    group.sum += row.group.sum;
    for (std::size_t b = 0; b < 2; ++b) group.runSquares[b] += row.group.runSquares[b];
    group.samples += row.group.samples;
    group.pixels += row.group.pixels;
    rays.total += row.rays.total;
    rays.afterFirstVertex += row.rays.afterFirstVertex;
  }
  const double samples = 2.0 * kProbeSamples * rows * columns;  // of each branch count
  stats.raysBefore = static_cast<double>(rays.total - rays.afterFirstVertex) / (2 * samples);
  stats.raysAfter = static_cast<double>(rays.afterFirstVertex) / (samples * (1 + kMeasuringBranches));
  // Each group's variances relative to its squared mean luminance; a black group measures nothing.
  std::vector<double> before, after;
  for (const Group& g : groups) {
    if (g.samples == 0 || !(g.sum > 0)) continue;
    const double mean = g.sum / static_cast<double>(g.samples);
    const double one = g.runSquares[0] / static_cast<double>(g.pixels) / (mean * mean);
    const double many = g.runSquares[1] / static_cast<double>(g.pixels) / (mean * mean);
    // one = V0 + V1, many = V0 + V1 / K.
    const double v1 = (one - many) * kMeasuringBranches / (kMeasuringBranches - 1.0);
    after.push_back(v1);
    before.push_back(one - v1);
  }
  if (after.empty()) return stats;
  const auto median = [](std::vector<double>& v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  stats.varianceBefore = median(before);
  stats.varianceAfter = median(after);
  stats.branches = branchesThatPay(*stats.raysBefore, *stats.raysAfter, *stats.varianceBefore, *stats.varianceAfter);
  return stats;
}

}  // namespace

RenderStats render(const Scene& scene, Film& film, const RenderOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };

  const PathIntegrator integrator(scene);
  const Camera& camera = *scene.camera;
  const std::unique_ptr<const Sampler> samplerPrototype =
      makeSampler(scene.settings.sampler, scene.settings.seed, camera.width());
  const CropWindow& crop = camera.crop();
  const std::vector<Tile> tiles = makeTiles(film, std::max(1u, options.tileSize));
  uint64_t rays = 0;  // of every pass, joined
  std::atomic<std::size_t> tilesDone{0};
  std::mutex progressMutex;
  std::optional<LightPathSource> lightSource;
  if (connectsLightPaths(scene.settings)) lightSource.emplace(scene);
  if (lightSource && lightSource->empty()) lightSource.reset();
  bool connects = lightSource.has_value();  // under auto, until the comparing pass says whether it pays
  const uint32_t lightPathsPerSample =
      std::max(kLeastLightPathsPerSample, camera.width() * camera.height() / kPixelsPerLightPath);

  auto renderPass = [&](const PassPlan& plan, double doneBefore, double passShare) {
    tilesDone = 0;
    std::vector<PassResult> tileResults(tiles.size());
    std::vector<PixelSpread> spreads(plan.compare ? std::size_t{film.width()} * film.height() : 0);
    const uint32_t passSamples = plan.last - plan.first;
    // One pool of light paths per sample index, whatever the pass: an image is the same for any
    // split into passes.
    std::vector<LightPathPool> lightPaths;
    if (plan.connects) {
      lightPaths.reserve(passSamples);
      for (uint32_t s = plan.first; s < plan.last; ++s)
        lightPaths.emplace_back(*lightSource, scene.settings.seed, s, lightPathsPerSample);
    }
    forEachInParallel(tiles.size(), [&](std::size_t t) {
      const Tile& tile = tiles[t];
      PassResult& out = tileResults[t];
      const std::unique_ptr<Sampler> sampler = samplerPrototype->clone();
      RayCounts tileRays;
      for (uint32_t y = tile.y0; y < tile.y1; ++y)
        for (uint32_t x = tile.x0; x < tile.x1; ++x) {
          const uint32_t fx = crop.x0 + x, fy = crop.y0 + y;
          // Whether the pixel gets what a comparing pass tries (guiding, connections).
          const bool tried = !plan.compare || (fx + fy) % 2 == 0;
          const uint64_t raysBefore = tileRays.total;
          double sum = 0, sumSquares = 0;
          for (uint32_t s = plan.first; s < plan.last; ++s) {
            sampler->startPixelSample(fx, fy, s);
            const auto [jx, jy] = sampler->getPixel2D();
            const Ray ray = camera.generateRay(fx + jx, fy + jy);
            const uint64_t sampleNumber = (uint64_t{fy} * camera.width() + fx) * passSamples + (s - plan.first);
            const bool record = sampleNumber % plan.recordStride == 0;
            out.recordedSamples += record && (plan.recordLight || plan.recordPaths);
            const Rgb L = integrator.radiance(
                ray, *sampler, tileRays,
                {tried ? plan.pathField : nullptr, record && plan.recordPaths ? &out.pathRecords : nullptr,
                 tried ? plan.lightField : nullptr, record && plan.recordLight ? &out.lightRecords : nullptr},
                plan.branches, plan.connects && tried ? &lightPaths[s - plan.first] : nullptr);
            film.add(x, y, L);
            const double luminance = L.luminance();
            sum += luminance;
            sumSquares += luminance * luminance;
          }
          if (plan.compare && passSamples > 1) {
            const double mean = sum / passSamples;
            spreads[std::size_t{y} * film.width() + x] = {
                mean, std::max(0.0, (sumSquares - passSamples * mean * mean) / (passSamples - 1)),
                tileRays.total - raysBefore};
          }
        }
      out.rays = tileRays;
      const std::size_t done = ++tilesDone;
      if (options.progress) {
        // Reported from whichever thread finished a tile, one at a time.
        std::lock_guard lock(progressMutex);
        options.progress(doneBefore + passShare * static_cast<double>(done) / tiles.size());
      }
    });
    PassResult joined;
    if (plan.compare && passSamples > 1)
      joined.halves = compareHalves(spreads, film.width(), film.height(), crop.x0, crop.y0, passSamples);
    std::size_t lightRecords = 0, pathRecords = 0;
    for (const PassResult& r : tileResults) {
      lightRecords += r.lightRecords.size();
      pathRecords += r.pathRecords.size();
    }
    joined.lightRecords.reserve(lightRecords);
    joined.pathRecords.reserve(pathRecords);
    for (PassResult& r : tileResults) {
      joined.lightRecords.insert(joined.lightRecords.end(), r.lightRecords.begin(), r.lightRecords.end());
      joined.pathRecords.insert(joined.pathRecords.end(), r.pathRecords.begin(), r.pathRecords.end());
      r.lightRecords = {};
      r.pathRecords = {};
      joined.recordedSamples += r.recordedSamples;
      rays += r.rays.total;
    }
    return joined;
  };

  RenderStats stats;
  GuidingStats& guidingStats = stats.guiding;
  const GuidingMode mode = scene.settings.guiding;
  // What is learned: the light where light samples are drawn, the paths' radiance where asked.
  const bool learnLight = mode != GuidingMode::Off && drawsLightSamples(scene.settings);
  const bool learnPaths = mode == GuidingMode::Paths;
  const bool learns = learnLight || learnPaths;
  // The fields the next passes use, built from the last recording pass's records.
  std::unique_ptr<GuidingField> lightField, pathField;
  const uint64_t pixels = uint64_t{film.width()} * film.height();
  const double fieldsLearned = (learnLight ? 1.0 : 0.0) + (learnPaths ? 1.0 : 0.0);
  double recordsPerSample = std::min(4u, scene.settings.maxDepth) * fieldsLearned;
  std::size_t learnedRecords = 0;  // by the last fields
  auto learnedEnough = [&] { return learnedRecords >= kEnoughRecords; };
  auto learn = [&](PassResult& pass) {
    learnedRecords = pass.lightRecords.size() + pass.pathRecords.size();
    if (pass.recordedSamples > 0)
      recordsPerSample = std::max(1.0, static_cast<double>(learnedRecords) / pass.recordedSamples);
    const auto buildStart = Clock::now();
    if (learnLight) lightField = std::make_unique<GuidingField>(std::move(pass.lightRecords));
    if (learnPaths) pathField = std::make_unique<GuidingField>(std::move(pass.pathRecords));
    guidingStats.fieldSeconds += std::chrono::duration<double>(Clock::now() - buildStart).count();
    guidingStats.spatialLeaves =
        (lightField ? lightField->spatialLeaves() : 0) + (pathField ? pathField->spatialLeaves() : 0);
    guidingStats.fieldBytes = (lightField ? lightField->bytes() : 0) + (pathField ? pathField->bytes() : 0);
    ++guidingStats.trainingPasses;
  };
  // A pass guided by the current fields (or not) that keeps about kMaxRecordsPerPass records at most.
  auto recordingPlan = [&](uint32_t first, uint32_t samples, bool guided, bool compare) {
    const double expected = static_cast<double>(pixels) * samples * recordsPerSample;
    return PassPlan{first,
                    first + samples,
                    guided ? lightField.get() : nullptr,
                    guided ? pathField.get() : nullptr,
                    compare,
                    learnLight,
                    learnPaths,
                    std::max<uint64_t>(1, static_cast<uint64_t>(std::ceil(expected / kMaxRecordsPerPass))),
                    stats.branching.branches};
  };
  // Under auto, whether the second pass's guided half paid.
  auto decide = [&](const PassResult& second) {
    if (mode != GuidingMode::Auto) return true;
    const double guided = second.halves[0].cost(), unguided = second.halves[1].cost();
    guidingStats.measuredGain = guided > 0 ? unguided / guided : 1.0;
    return *guidingStats.measuredGain >= kAutoGuidingGain;
  };
  stats.branching.branches = scene.settings.branches;
  if (scene.settings.branches == kAutoBranches) stats.branching = measureBranching(scene, integrator);
  auto finalPlan = [&](uint32_t first, uint32_t last) {
    PassPlan plan{first, last};
    if (guidingStats.guided) plan.lightField = lightField.get(), plan.pathField = pathField.get();
    plan.branches = stats.branching.branches;
    plan.connects = connects;
    return plan;
  };
  // Under auto, the first samples (at most kLightPathPassSamples) connect the pixels with x + y even
  // and not the others, and connections go on where that half's relative variance times rays per
  // sample is kLightPathMargin times less than the other's (passes of one sample measure nothing).
  const bool comparesConnections = connects && scene.settings.lightPaths == LightPathMode::Auto;
  auto comparingPlan = [&](uint32_t first, uint32_t last) {
    PassPlan plan = finalPlan(first, last);
    plan.compare = true;
    return plan;
  };
  auto decideConnections = [&](const PassResult& pass) {
    const double connected = pass.halves[0].cost(), unconnected = pass.halves[1].cost();
    stats.lightPathGain = connected > 0 ? unconnected / connected : 1.0;
    connects = *stats.lightPathGain >= kLightPathMargin;
  };

  if (options.seconds) {
    const double budget = *options.seconds;
    auto fraction = [&] { return std::min(1.0, elapsed() / budget); };
    if (learns) {
      // The first two passes, then doubling ones while the next should end within half the budget.
      PassResult first = renderPass(recordingPlan(stats.spp, 1, false, false), fraction(), 0.0);
      learn(first);
      const double secondStart = elapsed();
      PassResult second = renderPass(recordingPlan(stats.spp + 1, 2, true, mode == GuidingMode::Auto), fraction(), 0.0);
      stats.spp += 3;
      guidingStats.guided = decide(second);
      double lastPass = elapsed() - secondStart;
      if (guidingStats.guided) {
        learn(second);
        for (uint32_t size = 4; !learnedEnough() && elapsed() + 2.0 * lastPass <= budget / 2; size *= 2) {
          const double passStart = elapsed();
          PassResult pass = renderPass(recordingPlan(stats.spp, size, true, false), fraction(), 0.0);
          stats.spp += size;
          learn(pass);
          lastPass = elapsed() - passStart;
        }
      }
    }
    if (comparesConnections) {
      decideConnections(renderPass(comparingPlan(0, kLightPathPassSamples), fraction(), 0.0));
      stats.spp = kLightPathPassSamples;
    }
    while (stats.spp == 0 || elapsed() < budget) {
      renderPass(finalPlan(stats.spp, stats.spp + 1), fraction(), 0.0);
      ++stats.spp;
      if (options.progress) options.progress(fraction());
    }
  } else {
    const uint32_t total = scene.settings.spp;
    auto share = [&](uint32_t samples) { return static_cast<double>(samples) / total; };
    uint32_t done = 0;
    if (learns && total >= done + 3) {
      PassResult first = renderPass(recordingPlan(done, 1, false, false), share(done), share(1));
      learn(first);
      PassResult second =
          renderPass(recordingPlan(done + 1, 2, true, mode == GuidingMode::Auto), share(done + 1), share(2));
      done += 3;
      guidingStats.guided = decide(second);
      if (guidingStats.guided) {
        learn(second);
        for (uint32_t size = 4; !learnedEnough() && done + 2 * size <= total; done += size, size *= 2) {
          PassResult pass = renderPass(recordingPlan(done, size, true, false), share(done), share(size));
          learn(pass);
        }
      }
    }
    if (comparesConnections) {
      const uint32_t last = std::min(total, kLightPathPassSamples);
      decideConnections(renderPass(comparingPlan(0, last), 0.0, share(last)));
      done = last;
    }
    // With light paths, in passes of at most kLightPathPassSamples: their pools are megabytes.
    const uint32_t passSize = connects ? kLightPathPassSamples : total;
    for (uint32_t first = done; first < total; first += passSize) {
      const uint32_t last = std::min(total, first + passSize);
      renderPass(finalPlan(first, last), share(first), share(last - first));
    }
    stats.spp = total;
  }
  stats.connectsLightPaths = connects;
  stats.paths = pixels * stats.spp;
  stats.rays = rays;
  stats.seconds = elapsed();
  return stats;
}

}  // namespace acdf
