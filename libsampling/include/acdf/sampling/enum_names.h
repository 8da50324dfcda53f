#pragma once
// The one spelling of each value of an enum a user sees — on the command line, in scene files,
// JSON reports and table cache keys — from one table per enum: an enum's toString and parse…
// read the same list, and a parse error names every accepted spelling.

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace acdf {

template <class Enum>
struct EnumName {
  Enum value;
  std::string_view name;
};

// The name of `value` in `names`; "?" for a value the table lacks (a cast from a bad integer).
template <class Enum, std::size_t N>
constexpr std::string_view nameOf(const EnumName<Enum> (&names)[N], Enum value) {
  for (const EnumName<Enum>& n : names)
    if (n.value == value) return n.name;
  return "?";
}

// The value spelt `name`; throws std::invalid_argument "unknown <what> '<name>' (a, b or c)".
template <class Enum, std::size_t N>
Enum valueNamed(const EnumName<Enum> (&names)[N], std::string_view name, std::string_view what) {
  std::string accepted;
  for (std::size_t i = 0; i < N; ++i) {
    if (names[i].name == name) return names[i].value;
    accepted += (i == 0 ? "" : i + 1 == N ? " or " : ", ") + std::string(names[i].name);
  }
  throw std::invalid_argument("unknown " + std::string(what) + " '" + std::string(name) + "' (" + accepted + ")");
}

}  // namespace acdf
