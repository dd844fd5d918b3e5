// Mutant of task visualize_table: the file is opened with std::ios::app, so an existing picture is kept and the new one appended.
// Expected: loses points in visualize_table (e.g. VisualizeTable.OverwritesAnExistingFile fails; 1 of 12 tests fail).
//
// Task 3, reference solution with the one bug above: a picture of the table as an SVG file.
//
// SVG is a text format for vector drawings that every browser shows. A <circle> element takes
// its centre (cx, cy) and radius r. We draw in table units: the viewBox says which rectangle of
// those units fills the picture, here the table plus a small margin. SVG's y axis points down,
// so we write -y to show the table the way physicists draw it, with y pointing up.
#include "billiard/argument_checks.hpp"
#include "billiard/course.hpp"

#include <fstream>
#include <stdexcept>

namespace billiard {

void visualize_table(double table_radius, double circle_radius, int n,
                     const Coordinates& coordinates, const std::filesystem::path& svg_file) {
  checks::table(table_radius, circle_radius, n);
  checks::rows(coordinates, n, "coordinates");

  std::ofstream svg(svg_file, std::ios::app);
  if (!svg) throw std::runtime_error("svg_file = " + svg_file.string() + ": cannot open it for writing");
  svg.precision(10);  // enough digits that nobody sees rounding, even when zoomed in

  const double margin = 0.05 * table_radius;
  const double corner = -table_radius - margin, size = 2 * (table_radius + margin);
  svg << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"600\" height=\"600\" viewBox=\"" << corner << ' '
      << corner << ' ' << size << ' ' << size << "\">\n"
      << "  <title>" << n << " circles of radius " << circle_radius << " on a table of radius " << table_radius
      << "</title>\n"
      << "  <circle cx=\"0\" cy=\"0\" r=\"" << table_radius << "\" fill=\"#2e7d32\" stroke=\"#4e342e\" stroke-width=\""
      << 0.02 * table_radius << "\"/>\n";
  for (int i = 0; i < n; ++i) {
    svg << "  <circle cx=\"" << coordinates(i, 0) << "\" cy=\"" << -coordinates(i, 1) << "\" r=\"" << circle_radius
        << "\" fill=\"#fdd835\" stroke=\"#212121\" stroke-width=\"" << 0.05 * circle_radius << "\"/>\n";
  }
  svg << "</svg>\n";
  if (!svg.flush()) throw std::runtime_error("svg_file = " + svg_file.string() + ": writing it failed");
}

}  // namespace billiard
