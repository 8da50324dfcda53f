#include "acdf/brdf/table_options.h"

#include <charconv>
#include <cstdint>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "acdf/sampling/enum_names.h"
#include "acdf/sampling/option_error.h"

namespace acdf {

namespace {

using Type = TableOption::Type;
using Options = TabulatedBrdfOptions;

[[noreturn]] void notA(std::string_view key, std::string_view expected, std::string_view text) {
  throw OptionError("BRDF table", std::string(key), fmt::format("must be {}, got '{}'", expected, text));
}

uint32_t countFrom(std::string_view key, std::string_view text) {
  uint32_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc{} || end != text.data() + text.size())
    notA(key, "a whole number below 2^32", text);
  return value;
}

double numberFrom(std::string_view key, std::string_view text) {
  double value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc{} || end != text.data() + text.size()) notA(key, "a number", text);
  return value;
}

bool booleanFrom(std::string_view key, std::string_view text) {
  if (text != "true" && text != "false") notA(key, "true or false", text);
  return text == "true";
}

// An enum's value by one of its spellings; the parse's message lists them.
template <class Parse>
auto nameFrom(std::string_view key, std::string_view text, Parse parse) {
  try {
    return parse(text);
  } catch (const std::invalid_argument& e) {
    throw OptionError("BRDF table", std::string(key), e.what());
  }
}

std::string text(uint32_t value) { return std::to_string(value); }
std::string text(double value) { return fmt::format("{}", value); }  // shortest round trip
std::string text(bool value) { return value ? "true" : "false"; }

constexpr TableOption kTableOptions[] = {
    {"layout", Type::Name,
     "Table layout: 4d (theta_o, phi_o | theta_h, phi_h; every model) or isotropic (theta_o | theta_h, "
     "phi_h - phi_o; isotropic models)",
     [](Options& o, std::string_view t) { o.layout = nameFrom("layout", t, parseTableLayout); },
     [](const Options& o) { return std::string(toString(o.layout)); }},
    {"theta_out", Type::Count, "Cells of the outgoing theta_o over [0, pi/2)",
     [](Options& o, std::string_view t) { o.thetaOutCells = countFrom("theta_out", t); },
     [](const Options& o) { return text(o.thetaOutCells); }},
    {"phi_out", Type::Count, "Cells of the outgoing phi_o over [0, 2 pi) (4d layout)",
     [](Options& o, std::string_view t) { o.phiOutCells = countFrom("phi_out", t); },
     [](const Options& o) { return text(o.phiOutCells); }},
    {"theta_half", Type::Count, "Cells of the half vector's s = sqrt(theta_h / (pi/2)) over [0, 1)",
     [](Options& o, std::string_view t) { o.thetaHalfCells = countFrom("theta_half", t); },
     [](const Options& o) { return text(o.thetaHalfCells); }},
    {"phi_half", Type::Count,
     "Cells of the half vector's phi_h (isotropic: phi_h - phi_o) over [0, 2 pi); even when mirrored",
     [](Options& o, std::string_view t) { o.phiHalfCells = countFrom("phi_half", t); },
     [](const Options& o) { return text(o.phiHalfCells); }},
    {"mirror", Type::Boolean,
     "Isotropic layout: tabulate |phi_h - phi_o| in [0, pi) only (f is symmetric across the plane of incidence)",
     [](Options& o, std::string_view t) { o.mirror = booleanFrom("mirror", t); },
     [](const Options& o) { return text(o.mirror); }},
    {"supersampling", Type::Count, "Stratified points per cell and axis averaged into each cell's value",
     [](Options& o, std::string_view t) { o.supersampling = countFrom("supersampling", t); },
     [](const Options& o) { return text(o.supersampling); }},
    {"chi2_epsilon", Type::Number,
     "Adaptive tables' simplification tolerance (>= 0) in chi2-divergence, the relative variance each kept "
     "interval may add (not a CDF error, which an environment map's epsilon is)",
     [](Options& o, std::string_view t) { o.simplify.epsilon = numberFrom("chi2_epsilon", t); },
     [](const Options& o) { return text(o.simplify.epsilon); }},
    {"tolerance", Type::Name,
     "Adaptive conditional CDFs' tolerance: constant, or mass-scaled (looser where a slice has little mass)",
     [](Options& o, std::string_view t) { o.tolerance = nameFrom("tolerance", t, parseConditionalTolerance); },
     [](const Options& o) { return std::string(toString(o.tolerance)); }},
    {"slice_grouping", Type::Number,
     "Neighbouring outgoing slices share one distribution where that adds at most this chi2-divergence "
     "(0: one per slice)",
     [](Options& o, std::string_view t) { o.sliceGrouping = numberFrom("slice_grouping", t); },
     [](const Options& o) { return text(o.sliceGrouping); }},
    {"cosine_weight", Type::Number,
     "Defensive mixture in [0, 1]: the probability of drawing cosine-weighted instead of from the table",
     [](Options& o, std::string_view t) { o.cosineWeight = numberFrom("cosine_weight", t); },
     [](const Options& o) { return text(o.cosineWeight); }},
};

constexpr EnumName<Type> kTypeNames[] = {
    {Type::Count, "count"}, {Type::Number, "number"}, {Type::Boolean, "boolean"}, {Type::Name, "name"}};

}  // namespace

std::span<const TableOption> tableOptionList() { return kTableOptions; }

const TableOption* findTableOption(std::string_view key) {
  for (const TableOption& option : kTableOptions)
    if (option.key == key) return &option;
  return nullptr;
}

std::string_view toString(TableOption::Type type) { return nameOf(kTypeNames, type); }

}  // namespace acdf
