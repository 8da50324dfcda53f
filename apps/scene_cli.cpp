#include "scene_cli.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include <unistd.h>

namespace acdf::app {

namespace fs = std::filesystem;

namespace {

// A progress bar with an estimate of the time left on stderr, redrawn at most ten times a second.
class ProgressBar {
 public:
  void update(double fraction) {
    const auto now = Clock::now();
    if (fraction < 1.0 && now - lastDraw_ < std::chrono::milliseconds(100)) return;
    lastDraw_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const int filled = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * kWidth);
    const std::string eta = fraction > 0 ? fmt::format("ETA {:.0f} s", elapsed * (1.0 - fraction) / fraction) : "";
    std::fprintf(stderr, "\r[%s%s] %3.0f%% %-12s", std::string(filled, '#').c_str(),
                 std::string(kWidth - filled, '.').c_str(), 100.0 * fraction, eta.c_str());
    std::fflush(stderr);
  }
  ~ProgressBar() { std::fputs("\n", stderr); }

 private:
  static constexpr int kWidth = 40;
  Clock::time_point start_ = Clock::now(), lastDraw_{};
};

}  // namespace

void checkOutputPath(const std::string& path) {
  const fs::path p(path);
  const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw FileError(path, "the output directory does not exist");
  if (fs::is_directory(p, ec)) throw FileError(path, "is a directory");
  if (access(dir.c_str(), W_OK) != 0) throw FileError(path, "the output directory is not writable");
}

TableCache commandTableCache(bool disabled) {
  if (disabled) return TableCache::disabled();
  return TableCache::atDefaultLocation(
      [](const std::string& message) { std::fprintf(stderr, "acdf: warning: %s\n", oneLine(message).c_str()); });
}

RenderStats renderWithProgress(const Scene& scene, Film& film, std::optional<double> seconds) {
  RenderOptions options;
  options.seconds = seconds;
  std::optional<ProgressBar> bar;
  if (isatty(fileno(stderr))) {
    bar.emplace();
    options.progress = [&bar](double fraction) { bar->update(fraction); };
  }
  return render(scene, film, options);
}

}  // namespace acdf::app
