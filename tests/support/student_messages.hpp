// Failure messages for students: what was expected, what their code did, and a hint, in plain
// words. Use with any GoogleTest assertion:
//   EXPECT_LE(overlap, 1e-9) << explain("circles 2 and 5 not to overlap",
//                                        "they overlap by 0.3", "compare each new circle ...");
#pragma once

#include "billiard/course.hpp"
#include "billiard/not_implemented.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace billiard::testing {

// "\nExpected: ...\nYour code: ...\nHint: ..." (each part on its own line), and in a test that
// draws its failing case "Picture: FILE" (failure_pictures.hpp) after them.
std::string explain(std::string_view expected, std::string_view got, std::string_view hint);

// Streams its arguments into a string: text("circle ", i, " at ", row(c, i)).
template <typename... Parts>
std::string text(const Parts&... parts) {
  std::ostringstream out;
  out.precision(10);
  (out << ... << parts);
  return out.str();
}

// "Collision{time = 2, circle = 0, other = kWall} (circle 0 hits the wall after time 2)", or
// the same for two circles: what a student's function returned, in words.
std::string describe_collision(const Collision& collision);

// "(x, y)" for row i of an n x 2 array.
std::string row(const Eigen::Matrix<double, Eigen::Dynamic, 2>& rows, Eigen::Index i);

// Calls `call` and expects std::invalid_argument whose message mentions `argument`.
// `situation` says what was wrong with the input ("a negative circle_radius"). A
// NotImplemented error from a stub is passed on, so the test fails with its message.
template <typename Call>
void expect_invalid_argument(Call&& call, std::string_view situation, std::string_view argument,
                             std::string_view hint) {
  try {
    call();
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    if (message.find(argument) == std::string::npos) {
      ADD_FAILURE() << explain(text("the error message for ", situation, " to name the argument `", argument, "`"),
                               text("the message was \"", message, "\""), hint);
    }
    return;
  } catch (const NotImplemented&) {
    throw;
  } catch (const std::exception& error) {
    ADD_FAILURE() << explain(text("std::invalid_argument for ", situation),
                             text("threw a different kind of error: \"", error.what(), "\""), hint);
    return;
  }
  ADD_FAILURE() << explain(text("std::invalid_argument for ", situation),
                           "returned normally, without an error", hint);
}

}  // namespace billiard::testing
