#pragma once
// The options a user sets on a BRDF table (TabulatedBrdfOptions), as one list: the scene format's
// "table" keys, the command line's flags (--theta-half for theta_half) and the Python module's
// keywords all read it, so the three offer the same options under the same names, parsed and
// range-checked alike. A new option is one entry of the list (table_options.cpp).
//
// Each option reads and writes its value as text ("256", "5e-05", "true", "isotropic"): the form a
// flag arrives in, into which a JSON or Python value of the option's type converts losslessly
// (numbers as the shortest text that reads back to the same double).

#include <span>
#include <string>
#include <string_view>

#include "acdf/brdf/tabulated_brdf_sampler.h"

namespace acdf {

struct TableOption {
  // Count: a whole number of cells or points; Number: a real number; Boolean: true or false;
  // Name: one of the spellings of an enum (the help lists them).
  enum class Type { Count, Number, Boolean, Name };

  std::string_view key;  // as the scene format spells it
  Type type;
  std::string_view help;
  // Sets the option from its text. Throws OptionError("BRDF table", key, ...) for text that is
  // not of the option's type or spelling; ranges are validate()'s, once every option is set.
  void (*set)(TabulatedBrdfOptions& options, std::string_view text);
  // The option's value as text set() reads back (e.g. the defaults a help text shows).
  std::string (*get)(const TabulatedBrdfOptions& options);
};

// Every option users set on a table, in the order help texts list them.
std::span<const TableOption> tableOptionList();
// The option spelt `key`, or null.
const TableOption* findTableOption(std::string_view key);
// "count", "number", "boolean", "name".
std::string_view toString(TableOption::Type type);

}  // namespace acdf
