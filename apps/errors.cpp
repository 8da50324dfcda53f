#include "errors.h"

namespace acdf::app {

UsageError::UsageError(const std::string& message) : std::runtime_error(oneLine(message)) {}

std::string flagName(std::string_view option) {
  std::string flag = "--" + std::string(option);
  for (char& c : flag)
    if (c == '_') c = '-';
  return flag;
}

std::string flagError(const OptionError& e) { return flagName(e.option()) + " " + e.problem(); }

}  // namespace acdf::app
