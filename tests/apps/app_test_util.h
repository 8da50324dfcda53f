#pragma once
// Helpers for the acdf CLI tests: a per-test temporary directory, .npy file builders (valid and
// deliberately broken), and running build/bin/acdf as a subprocess.

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace acdf::apptest {

// A fresh directory for the current test, removed afterwards.
class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override;
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::filesystem::path dir_;
};

void writeFile(const std::string& path, const std::string& bytes);
std::string readFile(const std::string& path);

// The header dict a well-formed file of this dtype and shape has, e.g.
// "{'descr': '<f4', 'fortran_order': False, 'shape': (3, 4), }".
std::string npyDict(const std::string& descr, const std::vector<std::size_t>& shape, bool fortran = false);

// magic + version + header length + dict padded with spaces and '\n' to a multiple of 64 bytes.
std::string npyPreamble(const std::string& dict, int major = 1, int minor = 0);

template <class T>
std::string rawBytes(const std::vector<T>& values) {
  std::string out(values.size() * sizeof(T), '\0');
  if (!values.empty()) std::memcpy(out.data(), values.data(), out.size());
  return out;
}

// A complete, valid file.
std::string npyF4(const std::vector<std::size_t>& shape, const std::vector<float>& values, int major = 1);
std::string npyF8(const std::vector<std::size_t>& shape, const std::vector<double>& values, int major = 1);

struct RunResult {
  int exitCode = -1;  // exit status, or -1 when the process did not exit normally
  int signal = 0;     // terminating signal, if any
  std::string out, err;
  std::vector<std::string> errLines() const;
};

// Runs the acdf program (ACDF_EXE) with the arguments; stdout and stderr go to files in `scratch`.
RunResult runAcdf(const std::vector<std::string>& args, const std::filesystem::path& scratch);

// Exit status, signal, stdout (truncated) and stderr, for failure messages.
std::string describe(const RunResult& r);

// The CLI's contract for bad input: exit 2, no signal, nothing on stdout, exactly one stderr line
// (newline-terminated) that starts with `prefix` and contains `needle` (if not empty).
void expectOneLineFailure(const RunResult& r, const std::string& prefix, const std::string& needle);

std::string acdfExe();
std::string sourceDir();

// A peaked 2D function: a narrow Gaussian bump on a small constant floor.
std::vector<float> peakedGrid(std::size_t rows, std::size_t cols);

}  // namespace acdf::apptest
