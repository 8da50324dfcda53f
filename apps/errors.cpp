#include "errors.h"

namespace acdf::app {

UsageError::UsageError(const std::string& message) : std::runtime_error(oneLine(message)) {}

}  // namespace acdf::app
