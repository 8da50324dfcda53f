// A program whose chi-square registrations are wrong, run by ctest through
// expect_failure.cmake: it must exit non-zero, reporting after its last test a test that ran
// fewer chi-square tests than it registered, a registration that names no test, and a test
// registered twice.

#include <gtest/gtest.h>

#include "acdf/test_support/chi_square_registry.h"

namespace {

using acdf::test_support::chiSquareTestLevel;
using acdf::test_support::registerChiSquareTests;

ACDF_CHI_SQUARE_TEST(WrongCounts, RunsFewerThanRegistered, 2) { EXPECT_GT(chiSquareTestLevel(), 0.0); }

[[maybe_unused]] const bool kNamesNoTest = registerChiSquareTests("WrongCounts", "NoSuchTest", 1, __FILE__, __LINE__);

ACDF_CHI_SQUARE_TEST(WrongCounts, RegisteredTwice, 1) { EXPECT_GT(chiSquareTestLevel(), 0.0); }
[[maybe_unused]] const bool kSecondRegistration =
    registerChiSquareTests("WrongCounts", "RegisteredTwice", 1, __FILE__, __LINE__);

}  // namespace
