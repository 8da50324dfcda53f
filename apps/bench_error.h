#pragma once
// `acdf bench-error SCENE.json [--reference REF.exr] [--budgets 1,2,4,8,16 | --spp-budgets ...]
// [--out DIR]`: error against render time for every combination of sampling strategies (BRDF
// sampling × environment sampling × MIS mode), measured against a high-sample reference in one
// run on one machine. Writes results.csv / results.json (after every row, so an interrupted run
// resumes where it stopped), false-colour difference images, and the plots of
// bench/error_report.py. The engine is acdf/experiments/error_benchmark.h; this parses and prints.
// See docs/performance.md ("Error against time").

#include "command.h"

namespace CLI {
class App;
}

namespace acdf::app {

Command addBenchError(CLI::App& parent);

}  // namespace acdf::app
