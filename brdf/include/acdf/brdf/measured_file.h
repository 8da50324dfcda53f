#pragma once
// A measured BRDF file of either format, recognised by its content, not its name: an RGL tensor
// file (.bsdf, RglBrdf::isRglFile reads its magic) or else a MERL .binary table. Every tool and the
// scene loader open measured files through this one function.

#include <filesystem>
#include <memory>

#include "acdf/brdf/brdf_model.h"
#include "acdf/brdf/merl.h"

namespace acdf {

// `interpolation` applies to MERL tables; an RGL file interpolates its own slices (rgl.h). Throws
// FileError as the format's loader does (missing file, truncated, malformed).
std::shared_ptr<const BrdfModel> loadMeasuredBrdf(
    const std::filesystem::path& path, MerlBrdf::Interpolation interpolation = MerlBrdf::Interpolation::Nearest);

}  // namespace acdf
