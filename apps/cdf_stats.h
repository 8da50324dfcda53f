#pragma once
// `acdf cdf-stats INPUT ...`: builds the uniform, alias and adaptive distributions of a tabulated
// function and reports their size, build and sampling cost, and the adaptive one's accuracy.

#include "command.h"

namespace CLI {
class App;
}

namespace acdf::app {

Command addCdfStats(CLI::App& parent);

}  // namespace acdf::app
