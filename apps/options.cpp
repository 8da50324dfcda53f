#include "options.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include <fmt/format.h>

namespace acdf::app {

CLI::Validator nonNegativeInteger() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
        if (digits) return {};
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0' || !(v >= 0) || v > 0x1p53 || v != std::floor(v))
          return "must be a non-negative integer, got '" + text + "'";
        text = fmt::format("{}", static_cast<uint64_t>(v));
        return {};
      },
      "");
}

}  // namespace acdf::app
