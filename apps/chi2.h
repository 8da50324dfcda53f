#pragma once
// `acdf chi2 --envmap FILE --sampler S [--samples N] [--json]` and
// `acdf chi2 --brdf FILE --theta-o DEG --sampler S [table options] [--samples N] [--json]`: a
// chi-square goodness-of-fit test of a sampler against its own pdf, on the user's data. Exit 0 if
// it passes, 1 if it fails.

#include "command.h"

namespace CLI {
class App;
}

namespace acdf::app {

Command addChi2(CLI::App& parent);

}  // namespace acdf::app
