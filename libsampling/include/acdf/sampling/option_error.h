#pragma once
// The error an options struct's validator throws: which option is out of range and why, so each
// caller can name it in its own terms (the command line by its flag, the scene loader by its JSON
// path, a table cache reader by the file).

#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>

namespace acdf {

class OptionError : public std::invalid_argument {
 public:
  // `option` is the option's name as the scene format spells it ("epsilon", "max_points");
  // what() is "<scope>: <option> <problem>", e.g. "simplify: epsilon must be finite and >= 0".
  OptionError(const std::string& scope, std::string option, std::string problem)
      : std::invalid_argument(scope + ": " + option + " " + problem),
        option_(std::move(option)),
        problem_(std::move(problem)) {}
  const std::string& option() const { return option_; }
  const std::string& problem() const { return problem_; }

  // A value for a problem text, as printf's %g writes it ("0.5", "-1", "inf").
  static std::string number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
  }

 private:
  std::string option_;
  std::string problem_;
};

}  // namespace acdf
