#pragma once
// `acdf brdf-stats FILE [table options: --table 4d|isotropic --res R --epsilon E ...]
// [--interpolation M] [--samples N] [--quadrature] [--json]`: the paper's Table 1 for one measured BRDF (MERL .binary
// or RGL .bsdf, told apart by content) — the uniform and adaptive tables' resolution, bytes and
// compression, and each sampler's variance, speed and efficiency, with the file's own warps for an
// RGL file; with --quadrature, each sampler's mean and variance also by quadrature.
//
// The BRDF table options are shared with `acdf chi2 --brdf`, so both commands test the same
// samplers from the same flags.

#include <functional>
#include <map>
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

// The flags that choose a tabulated BRDF sampler's table: one per table option (table_options.h:
// --theta-half for theta_half, their text as given; absent or empty means TabulatedBrdfOptions'
// default), --res for every axis's cells at once, and the MERL interpolation.
struct BrdfTableArgs {
  std::map<std::string, std::string, std::less<>> given;
  std::string resolution;                 // e.g. 32x16x256x32 (4d) or 32x256x32 (isotropic)
  std::string interpolation = "nearest";  // nearest | trilinear
};

// Adds the table options' flags (--layout, also spelt --table, --theta-out, ..., --epsilon,
// --cosine-weight, ...), --res and --interpolation to `app`, bound to `args`; returns them (so a
// command can make them depend on its BRDF option). --res excludes the per-axis cell flags.
std::vector<CLI::Option*> addBrdfTableOptions(CLI::App& app, BrdfTableArgs& args);

// The table options the flags describe, with `method`. Throws UsageError naming the flag for a
// value of the wrong type or out of range, a malformed --res, or a table of more than 2^26 cells.
TabulatedBrdfOptions brdfTableOptions(const BrdfTableArgs& args, DimensionMethod method);

// A tabulated sampler of `model`; options the sampler rejects (an odd φ count for a mirrored
// isotropic table, say) become UsageError.
std::unique_ptr<TabulatedBrdfSampler> makeTabulatedSampler(std::shared_ptr<const BrdfModel> model,
                                                           const BrdfTableArgs& args, DimensionMethod method);

// The measured BRDF in `path` (acdf::loadMeasuredBrdf: RGL or MERL by content) with the flags'
// interpolation. Throws FileError ("<file>: <problem>", exit 2).
std::shared_ptr<const BrdfModel> loadMeasuredBrdf(const std::string& path, const BrdfTableArgs& args);

}  // namespace acdf::app
