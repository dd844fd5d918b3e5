// Task 5: movie -- an animated SVG of many collisions.
//
// Write movie below (declared in lib/include/billiard/course.hpp). Call propagate
// `collisions` times; after each call remember the positions of all circles and the time of
// the collision. Then write `svg_file` like visualize_table does, but give each circle two
// animations, one for its x and one for its y coordinate:
//   <circle cx="x0" cy="y0" r="1">
//     <animate attributeName="cx" dur="10s" repeatCount="indefinite"
//              values="x0;x1;x2;..." keyTimes="0;t1/T;t2/T;...;1"/>
//     <animate attributeName="cy" ... the same for y .../>
//   </circle>
// values: the positions at the start and after each collision; keyTimes: the time of each of
// those moments divided by the total time T. Between key frames the browser moves the
// circle in a straight line at constant speed: exactly the motion of the simulation.
// collisions = 0: write the table without animations. collisions < 0: throw
// std::invalid_argument naming `collisions`.
//
// Watch it: ./build.sh run  writes build/output/movie.svg; open it in a browser.
// Run this task's tests:   ./build.sh test -L movie
#include "billiard/argument_checks.hpp"
#include "billiard/course.hpp"
#include "billiard/not_implemented.hpp"

namespace billiard {

void movie(double table_radius, double circle_radius, int n, Coordinates& coordinates,
           Velocities& velocities, int collisions, const std::filesystem::path& svg_file) {
  // Delete these two lines and write the task.
  throw NotImplemented(5, "movie", "tasks/movie.cpp");
  (void)table_radius, (void)circle_radius, (void)n, (void)coordinates, (void)velocities, (void)collisions,
      (void)svg_file;
}

}  // namespace billiard
