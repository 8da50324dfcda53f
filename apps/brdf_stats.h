#pragma once
// `acdf brdf-stats FILE [--table 4d|isotropic] [--res R] [--epsilon E] [--interpolation M]
// [--samples N] [--quadrature] [--json]`: the paper's Table 1 for one measured BRDF (MERL .binary
// or RGL .bsdf, told apart by content) — the uniform and adaptive tables' resolution, bytes and
// compression, and each sampler's variance, speed and efficiency, with the file's own warps for an
// RGL file; with --quadrature, each sampler's mean and variance also by quadrature.
//
// The BRDF table options are shared with `acdf chi2 --brdf`, so both commands test the same
// samplers from the same flags.

#include <memory>
#include <string>
#include <vector>

#include "acdf/brdf/brdf_model.h"
#include "acdf/brdf/tabulated_brdf_sampler.h"
#include "command.h"

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace acdf::app {

Command addBrdfStats(CLI::App& parent);

// The flags that choose a tabulated BRDF sampler's table; empty strings mean "the defaults of
// TabulatedBrdfOptions".
struct BrdfTableArgs {
  std::string table = "4d";  // 4d | isotropic (parseTableLayout)
  std::string resolution;    // e.g. 32x16x256x32 (4d) or 32x256x32 (isotropic)
  double epsilon = TabulatedBrdfOptions{}.simplify.epsilon;
  std::string interpolation = "nearest";  // nearest | trilinear
  double cosineWeight = TabulatedBrdfOptions{}.cosineWeight;
  double sliceGrouping = TabulatedBrdfOptions{}.sliceGrouping;
};

// Adds --table, --res, --epsilon, --interpolation, --cosine-weight and --slice-grouping to `app`, bound to `args`;
// returns them (so a command can make them depend on its BRDF option).
std::vector<CLI::Option*> addBrdfTableOptions(CLI::App& app, BrdfTableArgs& args);

// The table options the flags describe, with `method`. Throws UsageError for a malformed --res
// or an --epsilon < 0.
TabulatedBrdfOptions brdfTableOptions(const BrdfTableArgs& args, DimensionMethod method);

// A tabulated sampler of `model`; options the sampler rejects (an odd φ count for a mirrored
// isotropic table, say) become UsageError.
std::unique_ptr<TabulatedBrdfSampler> makeTabulatedSampler(std::shared_ptr<const BrdfModel> model,
                                                           const BrdfTableArgs& args, DimensionMethod method);

// The measured BRDF in `path` (acdf::loadMeasuredBrdf: RGL or MERL by content) with the flags'
// interpolation. Throws FileError ("<file>: <problem>", exit 2).
std::shared_ptr<const BrdfModel> loadMeasuredBrdf(const std::string& path, const BrdfTableArgs& args);

}  // namespace acdf::app
