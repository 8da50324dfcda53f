#include "acdf/sampling/enum_names.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace acdf {
namespace {

enum class Fruit { Apple, Pear, Quince, Unnamed };
constexpr EnumName<Fruit> kFruitNames[] = {{Fruit::Apple, "apple"}, {Fruit::Pear, "pear"}, {Fruit::Quince, "quince"}};

TEST(EnumNames, EveryNameRoundTrips) {
  for (const EnumName<Fruit>& n : kFruitNames) {
    EXPECT_EQ(nameOf(kFruitNames, n.value), n.name);
    EXPECT_EQ(valueNamed(kFruitNames, n.name, "fruit"), n.value);
  }
  static_assert(nameOf(kFruitNames, Fruit::Pear) == "pear");
  EXPECT_EQ(nameOf(kFruitNames, Fruit::Unnamed), "?");
}

TEST(EnumNames, AnUnknownNameListsEveryAcceptedOne) {
  try {
    (void)valueNamed(kFruitNames, "Apple", "fruit");
    FAIL() << "a name of another case parsed";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "unknown fruit 'Apple' (apple, pear or quince)");
  }
  constexpr EnumName<Fruit> kOne[] = {{Fruit::Apple, "apple"}};
  EXPECT_THROW((void)valueNamed(kOne, "", "fruit"), std::invalid_argument);
}

}  // namespace
}  // namespace acdf
