#include "support/student_messages.hpp"

#include "support/failure_pictures.hpp"

namespace billiard::testing {

namespace {

// A part of several lines with each line after its first indented: only the message's own
// "Expected:", "Your code:", "Hint:" and "Picture:" start a line, whatever a student's output or
// exception message quoted in `got` holds (the grader reads the hint from the line that starts so).
std::string indented(std::string_view part) {
  std::string out;
  out.reserve(part.size());
  for (const char c : part) {
    out += c;
    if (c == '\n') out += "  ";
  }
  return out;
}

}  // namespace

std::string explain(std::string_view expected, std::string_view got, std::string_view hint) {
  const std::string picture = picture_of_failure(expected, got);
  return text("\nExpected: ", indented(expected), "\nYour code: ", indented(got), "\nHint: ", indented(hint), "\n",
              picture.empty() ? std::string() : text("Picture: ", picture, "\n"));
}

std::string describe_collision(const Collision& c) {
  if (c.other == kWall) {
    return text("Collision{time = ", c.time, ", circle = ", c.circle, ", other = kWall} (circle ", c.circle,
                " hits the wall after time ", c.time, ")");
  }
  return text("Collision{time = ", c.time, ", circle = ", c.circle, ", other = ", c.other, "} (circles ", c.circle,
              " and ", c.other, " collide after time ", c.time, ")");
}

std::string row(const Eigen::Matrix<double, Eigen::Dynamic, 2>& rows, Eigen::Index i) {
  return text("(", rows(i, 0), ", ", rows(i, 1), ")");
}

}  // namespace billiard::testing
