// Noisy but correct: writes a right picture, and megabytes of text to stdout and stderr.
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

#include "billiard/argument_checks.hpp"
#include "billiard/course.hpp"

namespace billiard {
void visualize_table(double table_radius, double circle_radius, int n, const Coordinates& coordinates,
                     const std::filesystem::path& svg_file) {
  checks::table(table_radius, circle_radius, n);
  checks::rows(coordinates, n, "coordinates");
  const std::string line(1000, 'x');
  for (int i = 0; i < 4000; ++i) {  // 4 MB to each stream
    std::fputs(line.c_str(), stdout);
    std::fputs(line.c_str(), stderr);
  }
  std::ofstream svg(svg_file);
  if (!svg) throw std::runtime_error("svg_file: cannot open it for writing");
  svg.precision(12);
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"-11 -11 22 22\">\n"
      << "<circle cx=\"0\" cy=\"0\" r=\"" << table_radius << "\"/>\n";
  for (int i = 0; i < n; ++i) {
    svg << "<circle cx=\"" << coordinates(i, 0) << "\" cy=\"" << coordinates(i, 1) << "\" r=\"" << circle_radius
        << "\"/>\n";
  }
  svg << "</svg>\n";
  if (!svg.flush()) throw std::runtime_error("svg_file: writing failed");
}
}  // namespace billiard
