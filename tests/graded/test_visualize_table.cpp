// Graded tests of task 3, visualize_table(table_radius, circle_radius, n, coordinates, svg_file):
// an SVG picture with the table as one <circle> and one <circle> per disc. The tests read the
// file with a tolerant SVG reader and check the geometry, not the formatting: any scale factor,
// any position of the table's centre and a flipped y axis are accepted. The coordinates come
// from the test fixtures, never from the student's init_billiard.
#include "support/fixtures.hpp"
#include "support/graded.hpp"
#include "support/student_messages.hpp"
#include "support/svg_reader.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace billiard::testing {
namespace {

namespace fs = std::filesystem;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Centres and radii must map back to the coordinates within this fraction of the table radius.
// Streams print 6 significant digits unless told otherwise, which the task does not forbid: a
// value v is then off by up to 5e-6 |v|, and with the table's centre at, e.g., (kR, kR) (SVG's
// origin in the corner) the written numbers reach 2kR, so the centres come back within about
// 1e-5 R. 1e-4 R leaves room for that and still catches every geometric mistake (they are of
// the order of a circle radius).
constexpr double kTolerance = 1e-4;

struct Table {
  double R;
  double a;
  int n;
  std::uint64_t seed;  // for scattered_circles
};

const std::vector<Table> kTables = {{10, 1, 10, 1}, {3.5, 0.25, 7, 2}, {250, 12, 5, 3}, {10, 1, 1, 4}};

std::string call(const Table& t) {
  return text("visualize_table(", t.R, ", ", t.a, ", ", t.n, ", coordinates, svg_file)");
}

// Calls visualize_table. NotImplemented passes on (the stub's message); any other exception is a
// failure, reported here.
bool draw(const Table& t, const Coordinates& coordinates, const fs::path& file) {
  try {
    visualize_table(t.R, t.a, t.n, coordinates, file);
    return true;
  } catch (const NotImplemented&) {
    throw;
  } catch (const std::exception& error) {
    ADD_FAILURE() << explain(text(call(t), " to write the picture to ", file),
                             text("it threw \"", error.what(), "\""),
                             "the arguments were valid; check that you open the file you are given (svg_file) and "
                             "only throw for the problems the contract lists");
    return false;
  }
}

std::optional<SvgDocument> read_picture(const Table& t, const fs::path& file,
                                        const std::string& hint =
                                            "open the file in a browser or a text editor to see the problem; every "
                                            "tag must be closed (<circle ... />) and attribute values quoted "
                                            "(cx=\"1.5\")") {
  try {
    return read_svg(file);
  } catch (const SvgError& error) {
    ADD_FAILURE() << explain(text(call(t), " to write a well-formed SVG file: <svg xmlns=\"http://www.w3.org/2000/svg\" "
                                              "...> with <circle .../> elements inside, then </svg>"),
                             error.what(), hint);
    return std::nullopt;
  }
}

// Draws table t (coordinates from the fixtures) and reads the picture back.
std::optional<SvgDocument> draw_and_read(const Table& t, const Coordinates& coordinates) {
  ScratchFolder folder;
  const fs::path file = folder / "table.svg";
  if (!draw(t, coordinates, file)) return std::nullopt;
  return read_picture(t, file);
}

// The table is the largest rendered circle; it fixes the scale (SVG units per table unit) and
// the origin. Returns nullptr (and reports) if there is none.
const SvgCircle* find_table(const SvgDocument& picture, const Table& t) {
  const SvgCircle* table = nullptr;
  for (const SvgCircle* circle : picture.rendered_circles()) {
    if (!table || circle->radius > table->radius) table = circle;
  }
  if (!table || !(table->radius > 0) || !std::isfinite(table->radius)) {
    ADD_FAILURE() << explain(text(call(t), " to draw the table as a <circle> with radius table_radius (times any scale "
                                           "factor)"),
                             table ? text("the largest <circle> (line ", table->line, ") has radius ", table->radius)
                                   : std::string("the file has no <circle> element"),
                             "write the table as <circle cx=\"...\" cy=\"...\" r=\"...\"/> with a positive r");
    return nullptr;
  }
  return table;
}

// --- The file --------------------------------------------------------------------------------

GRADED_TEST(VisualizeTable, WritesAnSvgFile, 2, visible) {
  const Table t{10, 1, 3, 5};
  const Coordinates coordinates = scattered_circles(t.R, t.a, t.n, t.seed);
  ScratchFolder folder;
  const fs::path file = folder / "table.svg";
  if (!draw(t, coordinates, file)) return;
  ASSERT_TRUE(fs::exists(file)) << explain(text(call(t), " to write the file ", file),
                                           "no file was created",
                                           "open std::ofstream with the path svg_file you are given, write to it and "
                                           "let it close (or close it) before returning");
  read_picture(t, file);
}

// Without xmlns="http://www.w3.org/2000/svg" on <svg>, a browser shows the file as plain XML
// text instead of a picture.
GRADED_TEST(VisualizeTable, SvgDeclaresTheSvgNamespace, 2, after_due_date) {
  const Table t{10, 1, 3, 5};
  const auto picture = draw_and_read(t, scattered_circles(t.R, t.a, t.n, t.seed));
  if (!picture) return;
  const std::string svg_namespace = "http://www.w3.org/2000/svg";
  bool declared = false;
  for (const auto& [name, value] : picture->root_attributes) {
    if (name.rfind("xmlns", 0) == 0 && value == svg_namespace) declared = true;
  }
  EXPECT_TRUE(declared) << explain(
      text("the <svg> element to declare xmlns=\"", svg_namespace, "\""),
      "it has no such attribute, so a browser opening the file shows text instead of a picture",
      "write <svg xmlns=\"http://www.w3.org/2000/svg\" ...>");
}

GRADED_TEST(VisualizeTable, DrawsTheTableAndOneCirclePerDisc, 2, visible) {
  for (const Table& t : {Table{10, 1, 0, 1}, Table{10, 1, 1, 2}, Table{10, 1, 10, 3}}) {
    const auto picture = draw_and_read(t, scattered_circles(t.R, t.a, t.n, t.seed));
    if (!picture) return;
    const auto circles = picture->rendered_circles();
    if (static_cast<int>(circles.size()) != t.n + 1) {
      ADD_FAILURE() << explain(text(call(t), " to draw ", t.n + 1, " <circle> elements: the table and ", t.n,
                                    " discs"),
                               text("the file has ", circles.size(), " <circle> elements"),
                               "write one <circle> for the table and one for each row of coordinates (loop i from 0 "
                               "to n - 1); other shapes (lines, text) are fine, but no other circles");
      return;
    }
  }
}

// --- Geometry --------------------------------------------------------------------------------

GRADED_TEST(VisualizeTable, TheWholeTableIsInThePicture, 2, visible) {
  // A browser shows the rectangle of the viewBox ("min-x min-y width height"); without one it
  // shows user coordinates from (0, 0) on, up to width and height if given. The table circle
  // must lie inside, up to 2% of its diameter (for a stroke drawn on its edge).
  const Table t{10, 1, 10, 7};
  const auto picture = draw_and_read(t, scattered_circles(t.R, t.a, t.n, t.seed));
  if (!picture) return;
  const SvgCircle* table = find_table(*picture, t);
  if (!table) return;
  double left = 0, top = 0, width = std::numeric_limits<double>::infinity(), height = width;
  std::string shown = "no viewBox: user coordinates from (0, 0) on";
  const auto& root = picture->root_attributes;
  if (const auto view_box = root.find("viewBox"); view_box != root.end()) {
    std::string numbers = view_box->second;
    std::replace(numbers.begin(), numbers.end(), ',', ' ');
    std::istringstream in(numbers);
    if (!(in >> left >> top >> width >> height) || !(width > 0) || !(height > 0)) {
      ADD_FAILURE() << explain(text(call(t), " to write a valid viewBox=\"min-x min-y width height\""),
                               text("viewBox=\"", view_box->second, "\""),
                               "write four numbers, e.g. viewBox=\"-11 -11 22 22\" for a table of radius 10");
      return;
    }
    shown = text("viewBox=\"", view_box->second, "\"");
  } else {
    if (root.count("width")) width = parse_length(root.at("width"), "the width of <svg>");
    if (root.count("height")) height = parse_length(root.at("height"), "the height of <svg>");
  }
  const double slack = 0.02 * 2 * table->radius;
  const bool inside = table->x - table->radius >= left - slack && table->y - table->radius >= top - slack &&
                      table->x + table->radius <= left + width + slack &&
                      table->y + table->radius <= top + height + slack;
  if (!inside) {
    ADD_FAILURE() << explain(
        text(call(t), " to show the whole table: the table circle (centre (", table->x, ", ", table->y,
             "), radius ", table->radius, ") inside the visible area"),
        text("the visible area is ", shown, ", so part of the table is cut off"),
        "with the table centred at (0, 0), choose viewBox=\"-R-m -R-m 2R+2m 2R+2m\" (a margin m), e.g. "
        "\"-11 -11 22 22\" for R = 10; a viewBox starting at 0 0 shows only one quarter of it");
  }
}

GRADED_TEST(VisualizeTable, DiscsHaveTheCircleRadiusAtTheTableScale, 2, visible) {
  for (const Table& t : kTables) {
    const auto picture = draw_and_read(t, scattered_circles(t.R, t.a, t.n, t.seed));
    if (!picture) return;
    const SvgCircle* table = find_table(*picture, t);
    if (!table) return;
    const double k = table->radius / t.R;  // SVG units per table unit
    for (const SvgCircle* disc : picture->rendered_circles()) {
      if (disc == table) continue;
      if (!disc->transform.keeps_circles_round()) {
        ADD_FAILURE() << explain(text(call(t), " to draw round discs"),
                                 text("the <circle> on line ", disc->line,
                                      " is under a transform that stretches x and y differently, so it is an ellipse"),
                                 "use the same scale factor for x and y (a flipped sign for y is fine)");
        return;
      }
      if (std::abs(disc->radius - k * t.a) > kTolerance * k * t.R) {
        ADD_FAILURE() << explain(
            text(call(t), ": the table is drawn with radius ", table->radius, " (", k,
                 " per unit of length), so every disc needs radius ", k, " * circle_radius = ", k * t.a),
            text("the <circle> on line ", disc->line, " has radius ", disc->radius, ", i.e. ", disc->radius / k,
                 " in table units"),
            "scale the table radius and the circle radius by the same factor; r is the radius, not the diameter");
        return;
      }
    }
  }
}

GRADED_TEST(VisualizeTable, DiscCentresAreAtTheCoordinates, 3, visible) {
  for (const Table& t : kTables) {
    const Coordinates coordinates = scattered_circles(t.R, t.a, t.n, t.seed);
    const auto picture = draw_and_read(t, coordinates);
    if (!picture) return;
    const SvgCircle* table = find_table(*picture, t);
    if (!table) return;
    const double k = table->radius / t.R;
    std::vector<const SvgCircle*> discs;
    for (const SvgCircle* circle : picture->rendered_circles()) {
      if (circle != table) discs.push_back(circle);
    }
    if (discs.empty()) {
      ADD_FAILURE() << explain(text(call(t), " to draw a <circle> for each of the ", t.n, " discs"),
                               "only the table's circle is there", "loop over the rows of coordinates");
      return;
    }
    // The y axis may point up or down (sign +1 or -1), the same way for all discs. For each
    // row, the nearest disc after mapping back to table units; keep the sign that fits best.
    struct Match {
      double error = 0;
      Eigen::Index row = 0;
      const SvgCircle* disc = nullptr;
    };
    auto worst_match = [&](double sign) {
      Match worst;
      worst.error = -1;
      for (Eigen::Index i = 0; i < coordinates.rows(); ++i) {
        Match best;
        best.error = kInf;
        for (const SvgCircle* disc : discs) {
          const double x = (disc->x - table->x) / k, y = sign * (disc->y - table->y) / k;
          const double error = std::hypot(x - coordinates(i, 0), y - coordinates(i, 1));
          if (error < best.error) best = Match{error, i, disc};
        }
        if (best.error > worst.error) worst = best;
      }
      return worst;
    };
    const Match up = worst_match(+1), down = worst_match(-1);
    const double sign = up.error <= down.error ? +1 : -1;
    const Match worst = sign > 0 ? up : down;
    if (!(worst.error <= kTolerance * t.R)) {
      const Eigen::Index i = worst.row;
      const double want_x = table->x + k * coordinates(i, 0), want_y = table->y + sign * k * coordinates(i, 1);
      const SvgCircle& disc = *worst.disc;
      const bool precision = worst.error < 1e-2 * t.R;
      ADD_FAILURE() << explain(
          text(call(t), ": the table is drawn centred at (", table->x, ", ", table->y, ") with radius ",
               table->radius, ", i.e. ", k, " per unit of length, so the disc in row ", i, " = ", row(coordinates, i),
               " belongs at (", want_x, ", ", want_y, ")", sign < 0 ? " (with y pointing up)" : "",
               ", within ", kTolerance * t.R * k),
          text("the nearest disc (line ", disc.line, ") is at (", disc.x, ", ", disc.y, "), which is (",
               (disc.x - table->x) / k, ", ", sign * (disc.y - table->y) / k, ") in table units, ", worst.error,
               " away"),
          precision ? "the position is nearly right: write numbers with more digits (e.g. out << "
                      "std::setprecision(10); std::fixed with few decimals loses precision) and use exactly the "
                      "table's scale and centre"
                    : "each disc's centre is cx = centre_x + k * x and cy = centre_y + k * y (or centre_y - k * y), "
                      "with the same centre and scale k as the table; cx and cy are the centre, not the corner");
      return;
    }
  }
}

// --- Files -----------------------------------------------------------------------------------

// Drawing into an existing, longer file must replace it, not append to it or leave its end.
GRADED_TEST(VisualizeTable, OverwritesAnExistingFile, 2, visible) {
  const Table t{10, 1, 3, 6};
  const Coordinates coordinates = scattered_circles(t.R, t.a, t.n, t.seed);
  ScratchFolder folder;
  const fs::path file = folder / "table.svg";
  {
    std::ofstream old(file);
    old << "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"-100 -100 200 200\">\n";
    old << "<!-- an older picture, longer than the new one -->\n";
    for (int i = 0; i < 60; ++i) old << "<circle cx=\"" << i << "\" cy=\"" << -i << "\" r=\"0.5\" fill=\"red\"/>\n";
    old << "</svg>\n";
  }
  if (!draw(t, coordinates, file)) return;
  const std::string hint =
      "open the file with std::ofstream out(svg_file); (mode std::ios::out, which empties an existing file), not "
      "with std::ios::app or std::ios::in | std::ios::out, which keep the old content";
  const auto picture = read_picture(t, file, hint);
  if (!picture) return;
  const auto circles = picture->rendered_circles();
  EXPECT_EQ(static_cast<int>(circles.size()), t.n + 1) << explain(
      text(call(t), " to replace an existing file ", file, " (which had 60 circles) by a picture with ", t.n + 1,
           " circles"),
      text("the file has ", circles.size(), " circles"), hint);
}

GRADED_TEST(VisualizeTable, ReportsAFileThatCannotBeWritten, 2, after_due_date) {
  const Table t{10, 1, 3, 7};
  const Coordinates coordinates = scattered_circles(t.R, t.a, t.n, t.seed);
  ScratchFolder folder;
  const fs::path blocker = folder / "plain_file";
  std::ofstream(blocker) << "a regular file, not a folder\n";
  const fs::path file = blocker / "table.svg";  // a path under a regular file cannot be created
  const std::string hint =
      "after opening, check the stream: if (!out) throw std::runtime_error(\"cannot write \" + svg_file.string()); "
      "std::ofstream does not throw by itself, it just ignores everything written to it";
  try {
    visualize_table(t.R, t.a, t.n, coordinates, file);
  } catch (const NotImplemented&) {
    throw;
  } catch (const std::runtime_error&) {
    return;  // what the contract asks for (std::filesystem and stream errors derive from it too)
  } catch (const std::exception& error) {
    ADD_FAILURE() << explain(text("std::runtime_error when the file ", file, " cannot be created"),
                             text("it threw a different kind of error: \"", error.what(), "\""),
                             text("the arguments were valid, the file system failed, which is a std::runtime_error; ",
                                  hint));
    return;
  }
  ADD_FAILURE() << explain(text("std::runtime_error when the file ", file, " cannot be created (", blocker,
                                " is a file, not a folder)"),
                           "returned normally, so the picture was silently lost", hint);
}

// --- Invalid arguments -------------------------------------------------------------------------

void expect_rejected(double R, double a, int n, const Coordinates& coordinates, const std::string& situation,
                     const std::string& argument, const std::string& hint) {
  ScratchFolder folder;
  const fs::path file = folder / "table.svg";
  expect_invalid_argument([&] { visualize_table(R, a, n, coordinates, file); }, situation, argument, hint);
}

GRADED_TEST(VisualizeTable, RejectsTableRadiusThatIsNotPositiveAndFinite, 1, after_due_date) {
  const Coordinates coordinates = scattered_circles(10, 1, 3, 8);
  for (const double R : {0.0, -10.0, kNaN, kInf}) {
    expect_rejected(R, 1, 3, coordinates, text("table_radius = ", R), "table_radius",
                    "check that table_radius is finite (std::isfinite) and positive before writing anything, and "
                    "throw std::invalid_argument naming table_radius otherwise");
  }
}

GRADED_TEST(VisualizeTable, RejectsCircleRadiusThatIsNotPositiveAndFinite, 1, after_due_date) {
  const Coordinates coordinates = scattered_circles(10, 1, 3, 8);
  for (const double a : {0.0, -1.0, kNaN, -kInf}) {
    expect_rejected(10, a, 3, coordinates, text("circle_radius = ", a), "circle_radius",
                    "check that circle_radius is finite (std::isfinite) and positive before writing anything, and "
                    "throw std::invalid_argument naming circle_radius otherwise");
  }
}

GRADED_TEST(VisualizeTable, RejectsCircleRadiusNotSmallerThanTableRadius, 1, after_due_date) {
  const Coordinates coordinates = Coordinates::Zero(1, 2);
  for (const double a : {10.0, 15.0}) {
    expect_rejected(10, a, 1, coordinates, text("circle_radius = ", a, " >= table_radius = 10 with n = 1"),
                    "circle_radius",
                    "a circle only fits on the table if circle_radius < table_radius; throw std::invalid_argument "
                    "naming circle_radius otherwise");
  }
}

GRADED_TEST(VisualizeTable, RejectsCoordinatesWithWrongRowCount, 1, after_due_date) {
  struct Case {
    int n;
    int rows;
  };
  for (const Case c : {Case{3, 2}, Case{3, 4}, Case{0, 1}}) {
    expect_rejected(10, 1, c.n, scattered_circles(10, 1, c.rows, 9),
                    text("n = ", c.n, " with coordinates of ", c.rows, " rows"), "coordinates",
                    "check coordinates.rows() == n before writing and throw std::invalid_argument naming "
                    "`coordinates` otherwise");
  }
}

GRADED_TEST(VisualizeTable, RejectsNegativeNumberOfCircles, 1, after_due_date) {
  expect_rejected(10, 1, -1, Coordinates(0, 2), "n = -1", "n",
                  "check n >= 0 at the start and throw std::invalid_argument naming n otherwise");
}

}  // namespace
}  // namespace billiard::testing
