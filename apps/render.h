#pragma once
// `acdf render SCENE -o IMAGE.exr [--spp N | --time SECONDS] [strategy overrides] [--json]`:
// renders a scene file (docs/scene-format.md) with the MIS path tracer of acdf::integrator into a
// linear float EXR and an sRGB PNG preview.

#include "command.h"

namespace CLI {
class App;
}

namespace acdf::app {

Command addRender(CLI::App& parent);

}  // namespace acdf::app
