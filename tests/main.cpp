// GoogleTest main with MPI and Kokkos initialised through Tpetra; only rank 0 reports.
// A run that would pass without testing what it names fails: every positive pattern of
// --gtest_filter must match a test that ran (a pattern that matches nothing is a typo that
// silently drops tests), and a GTEST_SKIP fails unless the environment expects it
// (IGACONTACT_EXPECTED_SKIPS = the number of tests that must skip; 0 when unset).
#include <gtest/gtest.h>
#include <Tpetra_Core.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

// gtest's filter syntax: '*' any string, '?' any character
bool glob(const char* p, const char* s) {
  if (*p == '\0') return *s == '\0';
  if (*p == '*') return glob(p + 1, s) || (*s != '\0' && glob(p, s + 1));
  return *s != '\0' && (*p == '?' || *p == *s) && glob(p + 1, s + 1);
}

// the positive patterns of the filter (before a '-'), each of which some test that ran matches
std::vector<std::string> unmatched_patterns(const ::testing::UnitTest& unit, const std::string& filter) {
  std::vector<std::string> patterns, unmatched;
  const std::string positive = filter.substr(0, filter.find('-'));
  for (size_t b = 0; b <= positive.size();) {
    const size_t e = std::min(positive.find(':', b), positive.size());
    if (e > b) patterns.push_back(positive.substr(b, e - b));
    b = e + 1;
  }
  for (const std::string& p : patterns) {
    bool hit = false;
    for (int i = 0; i < unit.total_test_suite_count() && !hit; ++i) {
      const ::testing::TestSuite& ts = *unit.GetTestSuite(i);
      for (int j = 0; j < ts.total_test_count() && !hit; ++j) {
        const ::testing::TestInfo& t = *ts.GetTestInfo(j);
        hit = t.should_run() && glob(p.c_str(), (std::string(ts.name()) + "." + t.name()).c_str());
      }
    }
    if (!hit) unmatched.push_back(p);
  }
  return unmatched;
}

}  // namespace

int main(int argc, char** argv) {
  Tpetra::ScopeGuard guard(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  const bool root = Tpetra::getDefaultComm()->getRank() == 0;
  auto& unit = *::testing::UnitTest::GetInstance();
  if (!root) {
    auto& listeners = unit.listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int rc = RUN_ALL_TESTS();   // the filter is applied here
  const std::string filter = GTEST_FLAG_GET(filter);
  const std::vector<std::string> unmatched = unmatched_patterns(unit, filter);
  if (unit.test_to_run_count() == 0 || !unmatched.empty()) {
    if (root) {
      std::fprintf(stderr, "FAIL: --gtest_filter=%s: %d test(s) ran; patterns matching no test:", filter.c_str(),
                   unit.test_to_run_count());
      for (const std::string& p : unmatched) std::fprintf(stderr, " %s", p.c_str());
      std::fprintf(stderr, "\n");
    }
    return 1;
  }
  const char* env = std::getenv("IGACONTACT_EXPECTED_SKIPS");
  const int expected = env ? std::atoi(env) : 0;
  if (unit.skipped_test_count() != expected) {
    if (root)
      std::fprintf(stderr, "FAIL: %d test(s) skipped, %d expected (IGACONTACT_EXPECTED_SKIPS): a skip is not a pass\n",
                   unit.skipped_test_count(), expected);
    return 1;
  }
  return rc;
}
