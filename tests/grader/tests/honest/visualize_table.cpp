// Task 3, written apart from the reference solution: a correct visualize_table as a student
// might write it, one element per statement, that the class grader's copy finder must not call
// a copy although both write the same SVG elements with the same stream.
#include "billiard/argument_checks.hpp"
#include "billiard/course.hpp"

#include <fstream>
#include <stdexcept>
#include <string>

namespace billiard {

namespace {

void write_circle(std::ostream& out, double x, double y, double r, const std::string& colour) {
  out << "<circle cx=\"" << x << "\" cy=\"" << y << "\" r=\"" << r << "\" fill=\"" << colour << "\"/>\n";
}

}  // namespace

void visualize_table(double table_radius, double circle_radius, int n,
                     const Coordinates& coordinates, const std::filesystem::path& svg_file) {
  checks::table(table_radius, circle_radius, n);
  checks::rows(coordinates, n, "coordinates");
  std::ofstream file(svg_file);
  if (!file.is_open()) {
    throw std::runtime_error("cannot write " + svg_file.string());
  }
  file.precision(12);
  const double half = 1.1 * table_radius;
  file << "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"";
  file << -half << " " << -half << " " << 2 * half << " " << 2 * half << "\">\n";
  write_circle(file, 0, 0, table_radius, "green");
  int i = 0;
  while (i < n) {
    const double x = coordinates(i, 0);
    const double y = coordinates(i, 1);
    write_circle(file, x, -y, circle_radius, "yellow");
    i++;
  }
  file << "</svg>\n";
  if (!file) {
    throw std::runtime_error("writing " + svg_file.string() + " failed");
  }
}

}  // namespace billiard
