// acdf: command-line front end of the adaptive-CDF importance-sampling toolkit.
//
// Exit status: 0 success; 2 a bad input file or a bad command line (one line on stderr,
// "acdf: <file>: <problem>" or "acdf: <problem>"); 1 an internal error.

#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench_error.h"
#include "brdf_stats.h"
#include "cdf_stats.h"
#include "chi2.h"
#include "command.h"
#include "env_gen.h"
#include "envmap_stats.h"
#include "errors.h"
#include "merl_gen.h"
#include "render.h"
#include "rgl_gen.h"

#ifndef ACDF_VERSION
#define ACDF_VERSION "unknown"
#endif

namespace {

constexpr int kExitInternal = 1;
constexpr int kExitBadInput = 2;

int report(const std::string& message, int code) {
  std::fprintf(stderr, "acdf: %s\n", acdf::oneLine(message).c_str());
  return code;
}

int run(int argc, char** argv) {
  CLI::App app{"acdf: adaptive-CDF importance sampling toolkit", "acdf"};
  app.set_version_flag("--version", std::string("acdf ") + ACDF_VERSION);
  app.require_subcommand(1);
  app.footer("Run 'acdf <command> --help' for a command's options.");

  std::vector<acdf::app::Command> commands;
  commands.push_back(acdf::app::addCdfStats(app));
  commands.push_back(acdf::app::addMerlGen(app));
  commands.push_back(acdf::app::addRglGen(app));
  commands.push_back(acdf::app::addBrdfStats(app));
  commands.push_back(acdf::app::addEnvGen(app));
  commands.push_back(acdf::app::addEnvmapStats(app));
  commands.push_back(acdf::app::addChi2(app));
  commands.push_back(acdf::app::addRender(app));
  commands.push_back(acdf::app::addBenchError(app));

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);  // --help, --version
    return report(std::string(e.what()) + " (see acdf --help)", kExitBadInput);
  }

  for (const auto& command : commands)
    if (command.app->parsed()) return command.run();
  return report("no command given (see acdf --help)", kExitBadInput);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const acdf::FileError& e) {
    return report(e.what(), kExitBadInput);
  } catch (const acdf::app::UsageError& e) {
    return report(e.what(), kExitBadInput);
  } catch (const std::bad_alloc&) {
    return report("out of memory", kExitInternal);
  } catch (const std::exception& e) {
    return report(std::string("internal error: ") + e.what(), kExitInternal);
  } catch (...) {
    return report("internal error: unknown exception", kExitInternal);
  }
}
