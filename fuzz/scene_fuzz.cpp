// Fuzzes the scene loader of `acdf render` (acdf/integrator/scene.h): any text either loads into a
// scene or raises FileError with a one-line message naming the scene file or the file it refers
// to. Seeds use constant environments: a map's table takes seconds to build under ASan. The scene "lives" in
// the source tree's scenes/ directory, so relative paths such as ../data/envmaps/… resolve; tables
// are built (never cached) only for what the scene uses.

#include <cstdint>
#include <string>

#include "acdf/integrator/scene.h"
#include "acdf/sampling/file_error.h"
#include "acdf/sampling/table_cache.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  using namespace acdf;
  const std::string file = ACDF_SOURCE_DIR "/scenes/fuzz.json";
  SceneAssets tables(TableCache::disabled());
  try {
    const Scene scene = loadSceneText(std::string(reinterpret_cast<const char*>(data), size), file, {}, tables);
    fuzz::require(scene.camera && scene.geometry && scene.environment, "scene: loaded without a part");
  } catch (const FileError& e) {
    // "<file>: <problem>", where the file is the scene or a file it refers to; what() is made one
    // line (a control character in the input quoted by the JSON parser becomes '?').
    const std::string message = e.what();
    fuzz::require(!e.file().empty() && message == oneLine(e.file()) + ": " + oneLine(e.problem()),
                  "scene: message does not name a file", message);
    fuzz::require(message.find('\n') == std::string::npos, "scene: message spans lines", message);
  }
  return 0;
}
