#pragma once
// `acdf merl-gen --nbrdf MATERIAL -o OUT.binary`: writes a full MERL-format BRDF table generated
// from a neural fit of a MERL material (or, with --preset NAME, from an analytic model);
// `acdf merl-gen --list` lists the materials.

#include "command.h"

namespace CLI {
class App;
}

namespace acdf::app {

Command addMerlGen(CLI::App& parent);

}  // namespace acdf::app
