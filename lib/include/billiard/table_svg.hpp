// An SVG picture of a table in the course's coordinates: x to the right, y up, the table's centre
// at the origin, lengths in table units. The `billiard` command's movie of a stage and the graded
// suites' pictures of a failing case both draw with it, so that a table, its walls and its
// circles look the same in both. SVG's y axis points down; every method takes table coordinates
// and flips y itself (svg_y), so callers never do.
#pragma once

#include "billiard/extensions.hpp"

#include <filesystem>
#include <sstream>
#include <string>
#include <string_view>

namespace billiard {

class TableSvg {
 public:
  // A picture of the table of radius table_radius with a margin of 5% around it, `width` pixels
  // wide, and `room_below` table radii of space under the table (for a legend).
  explicit TableSvg(double table_radius, double room_below = 0, int width = 600);

  // A length that scales with the table (1% of its radius): line widths and text sizes are
  // multiples of it, so pictures of tables of any size look alike.
  double unit() const { return table_radius_ / 100; }
  // The left edge and the bottom of the drawing (of the legend room, if any), in table coordinates.
  double left() const { return corner_; }
  double bottom() const { return bottom_; }

  // `attributes` below are further SVG attributes, written as given (class="..." fill="...").
  void title(std::string_view text);
  // Data for programs that read the picture back (such as JSON), in a <metadata> element.
  void metadata(std::string_view text);
  // The table's wall: a circle of radius table_radius at the origin, filled with `fill`.
  void table(std::string_view fill = kTableFill, std::string_view attributes = "");
  void wall(const Wall& wall, std::string_view attributes = "");
  void line(const Vector& from, const Vector& to, std::string_view attributes);
  // A circle; `children` (such as <animate> elements) is written inside it as given.
  void circle(const Vector& centre, double radius, std::string_view attributes, std::string_view children = "");
  // An arrow from `from` to `to`, its head scaled to `width`.
  void arrow(const Vector& from, const Vector& to, std::string_view colour, double width,
             std::string_view attributes = "");
  // Text whose baseline starts at `at`; `size` in table units; escaped for XML.
  void text(const Vector& at, std::string_view text, double size, std::string_view attributes = "");

  // Sizes the picture to where it is shown (a browser's window, an <img>): the whole of it, scaled
  // to fit whatever that place's shape, instead of `width` pixels wide.
  void fit_window() { fit_window_ = true; }

  // The picture so far, closed: a whole SVG document.
  std::string str() const;
  // Writes str() to `file`; throws std::runtime_error naming the file if that fails.
  void write(const std::filesystem::path& file) const;

  // SVG's coordinate for a table y (the axis points down in SVG).
  static double svg_y(double y) { return -y; }
  // `text` with &, <, > and " escaped for XML.
  static std::string escaped(std::string_view text);

  // The command's colours: a green table with a brown wall, yellow circles.
  static constexpr const char* kTableFill = "#2e7d32";
  static constexpr const char* kWallColour = "#4e342e";
  static constexpr const char* kCircleFill = "#fdd835";

 private:
  double table_radius_, corner_, bottom_;
  int width_;
  bool fit_window_ = false;
  std::ostringstream body_;
};

}  // namespace billiard
