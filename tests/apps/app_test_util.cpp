#include "app_test_util.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace acdf::apptest {

namespace fs = std::filesystem;

void TempDirTest::SetUp() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = std::string(info->test_suite_name()) + "." + info->name();
  for (char& c : name)
    if (c == '/') c = '_';
  dir_ = fs::temp_directory_path() / ("acdf_app_tests_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir_);
  fs::create_directories(dir_);
}

void TempDirTest::TearDown() {
  std::error_code ec;
  fs::remove_all(dir_, ec);
  fs::remove(dir_.parent_path(), ec);  // only succeeds once empty
}

void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path);
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string npyDict(const std::string& descr, const std::vector<std::size_t>& shape, bool fortran) {
  std::string s = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    if (i > 0) s += ", ";
    s += std::to_string(shape[i]);
  }
  if (shape.size() == 1) s += ",";
  s += ")";
  return "{'descr': '" + descr + "', 'fortran_order': " + (fortran ? "True" : "False") + ", 'shape': " + s + ", }";
}

std::string npyPreamble(const std::string& dict, int major, int minor) {
  const std::size_t lengthBytes = major == 1 ? 2 : 4;
  std::string header = dict;
  const std::size_t fixed = 8 + lengthBytes;
  while ((fixed + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::string out = "\x93NUMPY";
  out += static_cast<char>(major);
  out += static_cast<char>(minor);
  const auto len = static_cast<uint32_t>(header.size());
  for (std::size_t b = 0; b < lengthBytes; ++b) out += static_cast<char>((len >> (8 * b)) & 0xFF);
  return out + header;
}

std::string npyF4(const std::vector<std::size_t>& shape, const std::vector<float>& values, int major) {
  return npyPreamble(npyDict("<f4", shape), major) + rawBytes(values);
}

std::string npyF8(const std::vector<std::size_t>& shape, const std::vector<double>& values, int major) {
  return npyPreamble(npyDict("<f8", shape), major) + rawBytes(values);
}

std::vector<std::string> RunResult::errLines() const {
  std::vector<std::string> lines;
  std::istringstream in(err);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string acdfExe() { return ACDF_EXE; }
std::string sourceDir() { return ACDF_SOURCE_DIR; }

RunResult runAcdf(const std::vector<std::string>& args, const fs::path& scratch) {
  const std::string outPath = (scratch / "stdout.txt").string();
  const std::string errPath = (scratch / "stderr.txt").string();
  std::vector<std::string> argvStrings;
  argvStrings.push_back(acdfExe());
  argvStrings.insert(argvStrings.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argvStrings) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, outPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw std::runtime_error("cannot start " + acdfExe() + ": " + std::strerror(rc));

  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw std::runtime_error("waitpid failed");
  }
  RunResult r;
  if (WIFEXITED(status)) r.exitCode = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  r.out = readFile(outPath);
  r.err = readFile(errPath);
  return r;
}

std::vector<float> peakedGrid(std::size_t rows, std::size_t cols) {
  std::vector<float> v(rows * cols);
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c) {
      const double y = (static_cast<double>(r) + 0.5) / static_cast<double>(rows) - 0.3;
      const double x = (static_cast<double>(c) + 0.5) / static_cast<double>(cols) - 0.6;
      v[r * cols + c] = static_cast<float>(0.01 + 100.0 * std::exp(-(x * x + y * y) / (2 * 0.03 * 0.03)));
    }
  return v;
}

std::string describe(const RunResult& r) {
  return "exit " + std::to_string(r.exitCode) + (r.signal ? " signal " + std::to_string(r.signal) : "") +
         "\n--- stdout ---\n" + r.out.substr(0, 2000) + "\n--- stderr ---\n" + r.err;
}

void expectOneLineFailure(const RunResult& r, const std::string& prefix, const std::string& needle) {
  EXPECT_EQ(r.signal, 0) << describe(r);
  EXPECT_EQ(r.exitCode, 2) << describe(r);
  EXPECT_EQ(r.out, "") << describe(r);
  const auto lines = r.errLines();
  ASSERT_EQ(lines.size(), 1u) << describe(r);
  EXPECT_EQ(r.err.back(), '\n');
  EXPECT_EQ(lines[0].rfind(prefix, 0), 0u) << describe(r);
  if (!needle.empty()) {
    EXPECT_NE(lines[0].find(needle), std::string::npos) << "'" << needle << "' not in: " << lines[0];
  }
}

}  // namespace acdf::apptest
