#pragma once
// `acdf env-gen -o OUT.exr [--preset NAME] [--width W] [--height H] [--sun-… …]`: writes a
// procedural sun-and-sky environment map (acdf/envmap/sun_sky.h) as a float OpenEXR file.

#include "command.h"

namespace CLI {
class App;
}

namespace acdf::app {

Command addEnvGen(CLI::App& parent);

}  // namespace acdf::app
