#include "support/student_messages.hpp"

namespace billiard::testing {

std::string explain(std::string_view expected, std::string_view got, std::string_view hint) {
  return text("\nExpected: ", expected, "\nYour code: ", got, "\nHint: ", hint, "\n");
}

std::string row(const Eigen::Matrix<double, Eigen::Dynamic, 2>& rows, Eigen::Index i) {
  return text("(", rows(i, 0), ", ", rows(i, 1), ")");
}

}  // namespace billiard::testing
