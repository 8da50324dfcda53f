#pragma once
// `acdf envmap-stats FILE [--epsilon E] [--sanitize] [--json]`: the uniform, alias and adaptive
// sampling tables of an environment map (size, build time, the adaptive one's accuracy) and the
// variance and cost of an irradiance estimator with each strategy.

#include "command.h"

namespace CLI {
class App;
}

namespace acdf::app {

Command addEnvmapStats(CLI::App& parent);

}  // namespace acdf::app
