#include "errors.h"

namespace acdf::app {

UsageError::UsageError(const std::string& message) : std::runtime_error(oneLine(message)) {}

std::string flagError(const OptionError& e) {
  std::string flag = "--" + e.option();
  for (char& c : flag)
    if (c == '_') c = '-';
  return flag + " " + e.problem();
}

}  // namespace acdf::app
