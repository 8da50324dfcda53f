#include "acdf/test_support/chi_square_registry.h"

#include <algorithm>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "acdf/sampling/chi_square.h"

namespace acdf::test_support {
namespace {

struct Registration {
  std::string suite, name;
  uint32_t perTest = 0;
  std::string where;  // file:line of the registration
};

// GoogleTest names a TEST_P instance "Prefix/Suite.Name/Parameters", a TEST "Suite.Name".
bool matches(const Registration& r, const ::testing::TestInfo& test) {
  const std::string_view suite = test.test_suite_name(), name = test.name();
  const bool suiteMatches = suite == r.suite || (suite.ends_with(r.suite) && suite.size() > r.suite.size() &&
                                                 suite[suite.size() - r.suite.size() - 1] == '/');
  const bool nameMatches =
      name == r.name || (name.starts_with(r.name) && name.size() > r.name.size() && name[r.name.size()] == '/');
  return suiteMatches && nameMatches;
}

std::string fullName(const ::testing::TestInfo& test) {
  return std::string(test.test_suite_name()) + "." + test.name();
}

// Calls f(test) for every test GoogleTest knows in this program, whether it runs or not.
template <class F>
void forEachTest(F&& f) {
  const ::testing::UnitTest& unit = *::testing::UnitTest::GetInstance();
  for (int i = 0; i < unit.total_test_suite_count(); ++i) {
    const ::testing::TestSuite& suite = *unit.GetTestSuite(i);
    for (int j = 0; j < suite.total_test_count(); ++j) f(*suite.GetTestInfo(j));
  }
}

class Registry {
 public:
  static Registry& instance() {
    static Registry registry;
    return registry;
  }

  void add(Registration r) {
    std::lock_guard lock(mutex_);
    registrations_.push_back(std::move(r));
  }

  const Registration* find(const ::testing::TestInfo& test) const {
    for (const Registration& r : registrations_)
      if (matches(r, test)) return &r;
    return nullptr;
  }

  uint32_t familySize() const {
    uint32_t total = 0;
    forEachTest([&](const ::testing::TestInfo& test) {
      if (const Registration* r = find(test)) total += r->perTest;
    });
    return total;
  }

  // Counts one chi-square run of the current test; the failure message if it is not registered.
  std::string countRun() {
    std::lock_guard lock(mutex_);
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    if (test == nullptr) return "a chi-square test ran outside any test";
    const Registration* r = find(*test);
    if (r == nullptr) {
      return "chi-square test run by " + fullName(*test) +
             ", which is not registered: define it with ACDF_CHI_SQUARE_TEST or ACDF_CHI_SQUARE_TEST_P "
             "(chi_square_registry.h)";
    }
    uint32_t& runs = runs_[test];
    if (++runs > r->perTest) {
      return fullName(*test) + " ran chi-square test " + std::to_string(runs) + " but registered " +
             std::to_string(r->perTest) + " (" + r->where + ")";
    }
    return {};
  }

  // Before the tests: every registration names a test, and no test is registered twice.
  void checkRegistrations() {
    std::lock_guard lock(mutex_);
    runs_.clear();
    for (const Registration& r : registrations_) {
      std::size_t tests = 0;
      forEachTest([&](const ::testing::TestInfo& test) { tests += matches(r, test) ? 1 : 0; });
      if (tests == 0)
        ADD_FAILURE() << "chi-square registration of " << r.suite << "." << r.name << " (" << r.where
                      << ") names no test of this program";
    }
    forEachTest([&](const ::testing::TestInfo& test) {
      std::size_t registrations = 0;
      for (const Registration& r : registrations_) registrations += matches(r, test) ? 1 : 0;
      if (registrations > 1) ADD_FAILURE() << fullName(test) << " has " << registrations << " chi-square registrations";
    });
  }

  // After the tests: every registered test that passed ran all it registered.
  void checkRuns() {
    std::lock_guard lock(mutex_);
    forEachTest([&](const ::testing::TestInfo& test) {
      const Registration* r = find(test);
      if (r == nullptr || !test.should_run() || !test.result()->Passed()) return;
      const auto it = runs_.find(&test);
      const uint32_t runs = it == runs_.end() ? 0 : it->second;
      if (runs < r->perTest)
        ADD_FAILURE() << fullName(test) << " registered " << r->perTest << " chi-square tests (" << r->where
                      << ") but ran " << runs;
    });
  }

 private:
  std::mutex mutex_;
  std::vector<Registration> registrations_;
  std::map<const ::testing::TestInfo*, uint32_t> runs_;
};

// Checks the registrations before the first test and the runs after the last (each repetition).
class RegistryCheck : public ::testing::Environment {
 public:
  void SetUp() override { Registry::instance().checkRegistrations(); }
  void TearDown() override { Registry::instance().checkRuns(); }
};

}  // namespace

bool registerChiSquareTests(const char* suite, const char* name, uint32_t perTest, const char* file, int line) {
  static const bool environmentAdded = [] {
    ::testing::AddGlobalTestEnvironment(new RegistryCheck);  // GoogleTest owns it
    return true;
  }();
  (void)environmentAdded;
  Registry::instance().add({suite, name, perTest, std::string(file) + ":" + std::to_string(line)});
  return true;
}

uint32_t chiSquareFamilySize() { return Registry::instance().familySize(); }

double chiSquareTestLevel(double familyAlpha) {
  const std::string problem = Registry::instance().countRun();
  if (!problem.empty()) ADD_FAILURE() << problem;
  return sidakAlpha(familyAlpha, std::max(chiSquareFamilySize(), 1u));
}

}  // namespace acdf::test_support
