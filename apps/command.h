#pragma once
// A subcommand of the acdf program: its CLI11 sub-app and what to run when it was chosen.
// Each subcommand lives in its own file and exposes one `Command addXxx(CLI::App& parent)`.

#include <functional>

namespace CLI {
class App;
}

namespace acdf::app {

struct Command {
  CLI::App* app = nullptr;
  // Runs the subcommand after a successful parse; returns the exit code. Throws FileError /
  // UsageError for bad input; main() reports them.
  std::function<int()> run;
};

}  // namespace acdf::app
