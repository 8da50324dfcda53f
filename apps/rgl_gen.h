#pragma once
// `acdf rgl-gen --preset NAME -o OUT.bsdf`: writes an RGL `.bsdf` file (Dupuy & Jakob 2018) of an
// analytic GGX preset in the paper's parameterisation (rgl_synthesis.h).

#include "command.h"

namespace CLI {
class App;
}

namespace acdf::app {

Command addRglGen(CLI::App& parent);

}  // namespace acdf::app
