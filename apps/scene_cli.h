#pragma once
// What `acdf render` and `acdf bench-error` share: the output-path check made before rendering,
// the render with a terminal progress bar, the table cache with its warnings on stderr, and the
// parsing of an option value.

#include <optional>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "acdf/integrator/renderer.h"
#include "acdf/integrator/scene.h"
#include "acdf/sampling/table_cache.h"
#include "errors.h"
#include "options.h"

namespace acdf::app {

// Throws FileError unless a file can be written at `path` (its directory exists and is
// writable, and `path` is not a directory): fails before rendering, not after.
void checkOutputPath(const std::string& path);

// The on-disk table cache (disabled: --no-cache). Cache problems are warnings on stderr: a
// rejected file is rebuilt, a failed store only costs time.
TableCache commandTableCache(bool disabled);

// render(), for `seconds` (else the scene's sample count), with a progress bar when stderr is a
// terminal.
RenderStats renderWithProgress(const Scene& scene, Film& film, std::optional<double> seconds);

}  // namespace acdf::app
