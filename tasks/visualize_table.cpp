// Task 3: visualize_table -- a picture of the table as an SVG file.
//
// Write visualize_table below (declared in lib/include/billiard/course.hpp). Write the file
// `svg_file` in SVG, a text format for drawings that every browser shows. It needs
//   * the <svg ...> element around everything, with xmlns="http://www.w3.org/2000/svg" and a
//     viewBox="xmin ymin width height" that says which part of the plane is shown, e.g.
//     viewBox="-11 -11 22 22" for a table of radius 10 with a margin;
//   * the table wall as one circle:  <circle cx="0" cy="0" r="10" fill="green"/>
//   * each circle as one circle:     <circle cx="x_i" cy="y_i" r="circle_radius" fill="yellow"/>
// Write plain numbers into cx, cy and r (you may scale all of them by the same factor, and
// you may write -y because SVG's y axis points down); the tests read these <circle> elements.
// Open the file with std::ofstream; if it cannot be opened, throw std::runtime_error.
// Check the arguments first:  checks::table(...);  checks::rows(coordinates, n, "coordinates");
//
// Look at your picture: ./build.sh run  writes build/output/table.svg; open it in a browser.
// Run this task's tests:   ./build.sh test -L visualize_table
#include "billiard/argument_checks.hpp"
#include "billiard/course.hpp"
#include "billiard/not_implemented.hpp"

namespace billiard {

void visualize_table(double table_radius, double circle_radius, int n,
                     const Coordinates& coordinates, const std::filesystem::path& svg_file) {
  // Delete these two lines and write the task.
  throw NotImplemented(3, "visualize_table", "tasks/visualize_table.cpp");
  (void)table_radius, (void)circle_radius, (void)n, (void)coordinates, (void)svg_file;
}

}  // namespace billiard
