// The space the discs live in: a circular table, a periodic box, or closed outlines (boxes,
// polygons and curved outlines of segments and arcs) with their walls, plus any free segments,
// arcs and obstacles added to them.
//
//   billiard::Container table = billiard::sinai_billiard({0, 0}, {10, 10}, 2);
//   table.add_segment({1, 1}, {3, 1});                   // a free wall
//   billiard::Simulation sim(table);                     // fixed from here on
//
// A container is a value, made by one of the functions below for its shape and then extended.
// Each function and each add_ call checks its arguments when it is called and throws
// std::invalid_argument naming the argument and its value; a refused add_ call leaves the
// container as it was. Numbers must be finite and at most 1e50 in magnitude, and lengths (radii,
// sides) at least 1e-50, as a disc's radius (limits.hpp).
//
// The questions the engine asks of a container's geometry (where a periodic position wraps to,
// the nearest image, whether a disc is inside, how far it is from a wall) are answered once, in
// the library's internals (lib/src/engine/container_geometry.hpp).
#pragma once

#include "billiard/engine/plane.hpp"
#include "billiard/engine/wall.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace billiard {

// A closed outline for the inside test: its segments and arcs (in any order). A hole (an
// obstacle) keeps discs out whatever the other outlines say.
struct Outline {
  std::vector<WallShape> pieces;
  bool hole = false;
};

class Container;

// The shapes. Angles in radians, counter-clockwise from +x.
// A circular table of `radius` centred at the origin; discs live inside it.
Container circular_table(double radius);
// The periodic box [0, width) x [0, height): the standard bulk system. It has no walls, and none
// can be added to it.
Container periodic_box(double width, double height);
// The axis-aligned box [lower, upper]: four walls, discs inside.
Container box(const Vector& lower, const Vector& upper);
// A closed polygon (vertices N by 2, N >= 3, in order): one wall per side, discs inside.
Container polygon(const Coordinates& vertices);
// A stadium: two half circles of `radius` whose centres lie `length` apart on a horizontal line
// through `centre`, joined by two straight sides of that length; discs live inside it.
Container stadium(const Vector& centre, double radius, double length);
// The Sinai billiard: the box [lower, upper] with a disc obstacle of obstacle_radius at its
// middle (2 obstacle_radius below the smaller side).
Container sinai_billiard(const Vector& lower, const Vector& upper, double obstacle_radius);
// A mushroom: a half-disc cap of cap_radius above the horizontal line through `centre` (the
// middle of its flat side), on a rectangular stem stem_width wide (< 2 cap_radius) and
// stem_height tall below it; discs live inside it.
Container mushroom(const Vector& centre, double cap_radius, double stem_width, double stem_height);
// The union of circles (centres N by 2, radii N): its boundary is the arcs of each circle outside
// all the others, and the points where two such arcs meet are point walls. Discs live inside it.
Container union_of_circles(const Coordinates& centres, const std::vector<double>& radii);

class Container {
 public:
  // ---- More walls (not in a periodic box) ----
  // A straight wall from a to b (two-sided) and its two end points; returns the segment's index
  // in walls(). End points shared with earlier segments are not duplicated.
  int add_segment(const Vector& a, const Vector& b);
  // A circular arc (two-sided, like a segment: discs meet it from inside its circle or from
  // outside) of `radius` about `centre`, counter-clockwise from start_angle to end_angle
  // (0 < end_angle - start_angle <= 2 pi; 2 pi is a whole circle), and its two end points;
  // returns the arc's index in walls().
  int add_arc(const Vector& centre, double radius, double start_angle, double end_angle);
  // A disc obstacle: a whole circle that discs stay outside of.
  void add_obstacle(const Vector& centre, double radius);
  // An obstacle of any outlined shape (a box, polygon, stadium, mushroom or union of circles,
  // made by the functions above, without walls of its own added): discs stay outside of it.
  void add_obstacle(const Container& shape);

  // ---- What it is ----
  const std::vector<WallShape>& walls() const { return walls_; }  // table circle, segments, arcs, end points
  const std::vector<Outline>& outlines() const { return outlines_; }
  bool has_table() const { return has_table_; }
  double table_radius() const { return table_radius_; }  // 0 without a table
  bool periodic() const { return periodic_; }
  const Vector& period() const { return period_; }  // width and height of the periodic box; (0, 0) if none

  // ---- Saving and loading (snapshot.cpp; the format is that of Simulation::to_bytes) ----
  // The container as bytes, and back: from_bytes refuses (std::invalid_argument, naming
  // `source`) anything that is not such bytes, unchanged, from this format version.
  std::string to_bytes() const;
  static Container from_bytes(std::string_view bytes, const std::string& source = "the data");

 private:
  Container() = default;  // (made by the shape functions only: a container always holds discs in)
  friend Container circular_table(double);
  friend Container periodic_box(double, double);
  friend Container polygon(const Coordinates&);
  friend Container stadium(const Vector&, double, double);
  friend Container mushroom(const Vector&, double, double, double);
  friend Container union_of_circles(const Coordinates&, const std::vector<double>&);
  friend struct ContainerFields;  // (reads and writes the members below, for to_bytes)

  // A container of one closed outline (or a hole); end points closer than `merge` are one.
  static Container of_outline(std::vector<WallShape> pieces, double merge = 0.0);
  void refuse_in_periodic_box(const char* call) const;
  void add_outline(Outline outline, double merge = 0.0);
  void add_wall_with_ends(const WallShape& wall, double merge = 0.0);

  std::vector<WallShape> walls_;
  std::vector<Outline> outlines_;
  bool has_table_ = false;
  double table_radius_ = 0.0;
  bool periodic_ = false;
  Vector period_ = Vector::Zero();
  int free_walls_ = 0;  // segments and arcs added on their own, outside any outline
};

}  // namespace billiard
