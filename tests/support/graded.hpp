// Points and visibility of graded tests, kept next to each test:
//
//   GRADED_TEST(Propagate, HeadOnCollisionAtTimeFour, 2, visible) { ... }
//
// is a GoogleTest TEST worth 2 points. A task's maximum is the sum of the points in its suite;
// its score the sum over its passing tests. Visibility, as on Gradescope:
//   visible         shown to the student at once (the sanity tests);
//   after_due_date  result and feedback shown after the due date;
//   hidden          never shown; feedback is replaced by a neutral line.
// `test_<task> --list-graded` prints one JSON object per test ({"test", "points",
// "visibility"}) for the grader, and fails if a test in the binary has no points.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace billiard::testing {

enum class Visibility { visible, after_due_date, hidden };

struct GradedTest {
  std::string name;  // "Suite.Name", as in --gtest_filter
  int points;
  Visibility visibility;
};

// Registers a test's points (called by GRADED_TEST before main runs); returns true.
bool register_graded(const char* suite, const char* name, int points, Visibility visibility);

// Everything registered, in registration order.
const std::vector<GradedTest>& graded_tests();

const char* to_string(Visibility visibility);

}  // namespace billiard::testing

#define GRADED_TEST(Suite, Name, Points, Shown)                                         \
  static_assert((Points) > 0, "a graded test is worth at least one point");            \
  [[maybe_unused]] static const bool graded_registration_##Suite##_##Name =            \
      ::billiard::testing::register_graded(#Suite, #Name, Points,                      \
                                           ::billiard::testing::Visibility::Shown);    \
  TEST(Suite, Name)
