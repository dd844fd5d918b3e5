#include "billiard/argument_checks.hpp"

#include "billiard/describe.hpp"
#include "wall_geometry.hpp"
#include "billiard/limits.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace billiard::checks {
namespace {

template <typename... Parts>
[[noreturn]] void fail(const Parts&... parts) {
  throw std::invalid_argument(describe(parts...));
}

// The numbers the course functions accept (billiard/limits.hpp): beyond them the squares and
// products overflow or underflow (circles placed outside a table of radius 1e300, say).
void positive_finite(double value, std::string_view name) {
  if (!limits::in_scale(value)) fail(name, " = ", value, ": ", limits::kMustBeInScale);
}

using limits::bounded;

}  // namespace

void count(int n) {
  if (n < 0) fail("n = ", n, ": the number of circles cannot be negative");
}

void table(double table_radius, double circle_radius, int n) {
  positive_finite(table_radius, "table_radius");
  positive_finite(circle_radius, "circle_radius");
  count(n);
  if (n > 0 && circle_radius >= table_radius) {
    fail("circle_radius = ", circle_radius, ": must be smaller than table_radius = ", table_radius,
         " for a circle to fit on the table");
  }
}

void rows(const Eigen::Matrix<double, Eigen::Dynamic, 2>& rows, int n, std::string_view name) {
  count(n);
  if (rows.rows() != n) fail(name, " has ", rows.rows(), " rows: expected one row per circle, n = ", n);
  for (Eigen::Index i = 0; i < rows.rows(); ++i) {
    if (!bounded(rows(i, 0), rows(i, 1))) {
      fail(name, " row ", i, " = (", rows(i, 0), ", ", rows(i, 1), "): ", limits::kMustBeBounded);
    }
  }
}

void placement(double table_radius, double circle_radius, const Coordinates& coordinates) {
  const double tolerance = 1e-9 * table_radius;
  const double reach = table_radius - circle_radius + tolerance;
  const double diameter = 2 * circle_radius - tolerance;
  const Eigen::Index n = coordinates.rows();
  // The first failure in row order, as if each row were checked (inside the table, then against
  // every later row) before the next: the first row that sticks out, unless a row before it
  // overlaps a later one.
  Eigen::Index sticks_out = n;
  for (Eigen::Index i = 0; i < n && sticks_out == n; ++i) {
    if (coordinates.row(i).squaredNorm() > reach * reach) sticks_out = i;
  }
  // Cells of side |diameter|: two circles closer than that lie in neighbouring cells, so each
  // row is compared with the 3x3 block of cells around it, not with every row (the sectors
  // stage's efficiency tests step tables of 200,000 circles).
  const double side = std::abs(diameter);
  if (side > 0 && sticks_out > 0) {
    const auto cell_of = [side](double x) {
      constexpr double kFar = 1 << 30;  // farther cells share one: only far circles go there
      return static_cast<std::int64_t>(std::floor(std::clamp(x / side, -kFar, kFar)));
    };
    const auto key = [](std::int64_t cx, std::int64_t cy) {
      return (static_cast<std::uint64_t>(cx) << 32) ^ (static_cast<std::uint64_t>(cy) & 0xffffffffU);
    };
    std::unordered_map<std::uint64_t, std::vector<Eigen::Index>> cells;
    cells.reserve(static_cast<std::size_t>(n));
    for (Eigen::Index j = 0; j < n; ++j) cells[key(cell_of(coordinates(j, 0)), cell_of(coordinates(j, 1)))].push_back(j);
    for (Eigen::Index i = 0; i < sticks_out; ++i) {
      const std::int64_t cx = cell_of(coordinates(i, 0)), cy = cell_of(coordinates(i, 1));
      Eigen::Index first = n;
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
          const auto cell = cells.find(key(cx + dx, cy + dy));
          if (cell == cells.end()) continue;
          for (const Eigen::Index j : cell->second) {
            if (j > i && j < first && (coordinates.row(i) - coordinates.row(j)).squaredNorm() < diameter * diameter) {
              first = j;
            }
          }
        }
      }
      if (first < n) {
        fail("coordinates rows ", i, " and ", first, ": circles overlap (centres ",
             (coordinates.row(i) - coordinates.row(first)).norm(), " apart, less than 2 circle_radius = ",
             2 * circle_radius, ")");
      }
    }
  }
  if (sticks_out < n) {
    const Eigen::Index i = sticks_out;
    fail("coordinates row ", i, " = (", coordinates(i, 0), ", ", coordinates(i, 1),
         "): circle sticks out of the table (its centre must be within table_radius - circle_radius = ",
         table_radius - circle_radius, " of the origin)");
  }
}

void vector(const Vector& value, std::string_view name) {
  if (!bounded(value(0), value(1))) fail(name, " = (", value(0), ", ", value(1), "): ", limits::kMustBeBounded);
}

void walls(double table_radius, const std::vector<Wall>& walls) {
  const double reach = table_radius * (1 + 1e-9);
  for (std::size_t k = 0; k < walls.size(); ++k) {
    for (const auto& [end, label] : {std::pair{walls[k].a, "a"}, std::pair{walls[k].b, "b"}}) {
      if (!end.allFinite() || end.squaredNorm() > reach * reach) {
        fail("walls[", k, "].", label, " = (", end(0), ", ", end(1),
             "): a wall's end points must be finite and inside the table (|", label, "| <= table_radius = ",
             table_radius, ")");
      }
    }
  }
}

double distance_to_wall(const Vector& p, const Wall& wall) {
  return distance_to_segment(p, wall.a, wall.b);
}

void clear_of_walls(double table_radius, double circle_radius, const Coordinates& coordinates,
                    const std::vector<Wall>& walls) {
  const double clearance = circle_radius - 1e-9 * table_radius;
  for (Eigen::Index i = 0; i < coordinates.rows(); ++i) {
    for (std::size_t k = 0; k < walls.size(); ++k) {
      const double distance = distance_to_wall(coordinates.row(i), walls[k]);
      if (distance < clearance) {
        fail("coordinates row ", i, " = (", coordinates(i, 0), ", ", coordinates(i, 1), "): circle overlaps walls[",
             k, "] (its centre is ", distance, " from the wall, less than circle_radius = ", circle_radius, ")");
      }
    }
  }
}

void cell_size(double table_radius, double circle_radius, double cell_size) {
  if (!(std::isfinite(cell_size) && cell_size >= 2 * circle_radius)) {
    fail("cell_size = ", cell_size, ": must be a finite number of at least 2 circle_radius = ", 2 * circle_radius);
  }
  if (2 * table_radius / cell_size > kMaxCellsAcross) {
    fail("cell_size = ", cell_size, ": too small, the table would be ", 2 * table_radius / cell_size,
         " cells across (at most ", kMaxCellsAcross, "); use a cell_size of at least ",
         2 * table_radius / kMaxCellsAcross);
  }
}

}  // namespace billiard::checks
