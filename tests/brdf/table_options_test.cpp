// The one list of BRDF table options (table_options.h) that the scene format, the command line
// and Python read: every option reads back what it writes, sets its own field only, and refuses
// text of another type naming itself.

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>

#include "acdf/brdf/table_options.h"
#include "acdf/sampling/option_error.h"

namespace acdf {
namespace {

// A value other than the default for every option; a new option must add one here.
const std::map<std::string, std::string, std::less<>> kOtherValues = {
    {"layout", "isotropic"}, {"theta_out", "8"},        {"phi_out", "4"},        {"theta_half", "64"},
    {"phi_half", "12"},      {"mirror", "false"},        {"supersampling", "3"},  {"chi2_epsilon", "0.000123"},
    {"tolerance", "constant"}, {"slice_grouping", "0.5"}, {"cosine_weight", "0.25"},
};

// Every option's text in `o`.
std::map<std::string, std::string, std::less<>> texts(const TabulatedBrdfOptions& o) {
  std::map<std::string, std::string, std::less<>> out;
  for (const TableOption& option : tableOptionList()) out[std::string(option.key)] = option.get(o);
  return out;
}

TEST(TableOptions, KeysAreUniqueAndFound) {
  std::set<std::string_view> keys;
  for (const TableOption& option : tableOptionList()) {
    EXPECT_TRUE(keys.insert(option.key).second) << option.key;
    EXPECT_EQ(findTableOption(option.key), &option);
    EXPECT_FALSE(option.help.empty()) << option.key;
    EXPECT_TRUE(kOtherValues.contains(option.key)) << option.key << ": add a value to kOtherValues";
  }
  EXPECT_EQ(findTableOption("theta_half_cells"), nullptr);
}

TEST(TableOptions, EachSetsItsOwnFieldAndReadsBack) {
  const auto defaults = texts(TabulatedBrdfOptions{});
  for (const TableOption& option : tableOptionList()) {
    TabulatedBrdfOptions o;
    const std::string& value = kOtherValues.find(option.key)->second;
    ASSERT_NE(value, defaults.find(option.key)->second) << option.key;
    option.set(o, value);
    auto expected = defaults;
    expected[std::string(option.key)] = value;
    EXPECT_EQ(texts(o), expected) << option.key;
    option.set(o, defaults.find(option.key)->second);
    EXPECT_EQ(texts(o), defaults) << option.key << ": the default's text reads back";
  }
}

TEST(TableOptions, NumbersReadBackExactly) {
  TabulatedBrdfOptions o;
  o.simplify.epsilon = 0.1 + 0.2;  // not the shortest decimal of 0.3
  TabulatedBrdfOptions back;
  findTableOption("chi2_epsilon")->set(back, findTableOption("chi2_epsilon")->get(o));
  EXPECT_EQ(back.simplify.epsilon, o.simplify.epsilon);
}

TEST(TableOptions, TextOfAnotherTypeNamesTheOption) {
  const std::map<TableOption::Type, std::vector<std::string>> bad = {
      {TableOption::Type::Count, {"", "-1", "3.5", "x", "4294967296", " 4"}},
      {TableOption::Type::Number, {"", "abc", "1e", "0.5x"}},
      {TableOption::Type::Boolean, {"", "yes", "1", "True"}},
      {TableOption::Type::Name, {"", "iso", "4D"}},
  };
  for (const TableOption& option : tableOptionList()) {
    for (const std::string& text : bad.at(option.type)) {
      TabulatedBrdfOptions o;
      try {
        option.set(o, text);
        ADD_FAILURE() << option.key << " accepted '" << text << "'";
      } catch (const OptionError& e) {
        EXPECT_EQ(e.option(), option.key);
      }
    }
  }
}

}  // namespace
}  // namespace acdf
