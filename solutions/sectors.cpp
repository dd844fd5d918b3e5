// Task 9, reference solution: the next collision through cells instead of all pairs.
//
// The table's bounding square [-R, R]^2 is cut into m x m square cells of side cell_size >= 2a.
// Two circles whose cells are not neighbours (not in one 3x3 block) have a whole cell between
// them, so they are more than cell_size >= 2a apart: they cannot touch before one of them moves
// into another cell. So within one call:
//   1. put every circle into its cell (O(n)); compute every wall time, the pair times with the
//      circles in the own and the 8 neighbouring cells (each pair once), and for every moving
//      circle the time it leaves its cell;
//   2. while the earliest cell crossing comes before the earliest collision found so far, move
//      that circle (logically: positions are r + v t from the start of the call) into the next
//      cell and test it against the circles in the row or column of cells that has just become
//      neighbouring;
//   3. then the earliest collision is certain: move every circle and collide as in propagate.
// All times are measured from the start of the call, so pair_time on the starting state gives
// the right answer whenever a pair is found. Nothing survives between calls.
#include "billiard/argument_checks.hpp"
#include "billiard/extensions.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace billiard {
namespace {

constexpr double kNever = std::numeric_limits<double>::infinity();

// Time until a circle at r moving with v touches the wall |r + v t| = reach (as in propagate).
double time_to_wall(const Vector& r, const Vector& v, double reach) {
  const double A = v.squaredNorm();
  if (A == 0) return kNever;
  const double B = r.dot(v);
  const double C = r.squaredNorm() - reach * reach;
  if (C >= 0 && B >= 0) return B > 0 ? 0.0 : kNever;  // on the wall by rounding: bounce now if outward
  const double root = std::sqrt(std::max(B * B - A * C, 0.0));
  const double t = B > 0 ? -C / (B + root) : (-B + root) / A;
  return std::max(t, 0.0);
}

// A circle leaving its cell through the face on `axis` (0: x, 1: y) at `time`.
struct Crossing {
  double time;
  int circle;
  int axis;
  bool operator>(const Crossing& other) const { return time > other.time; }
};

// The square cells: only the occupied ones are stored (a table may have 4096 x 4096 cells).
class Grid {
 public:
  Grid(double table_radius, double cell_size)
      : R_(table_radius), size_(cell_size), across_(std::max(1, static_cast<int>(std::ceil(2 * table_radius / cell_size)))) {}

  int across() const { return across_; }

  // The cell index along one axis of coordinate x: floor, so that a circle exactly on a face
  // belongs to the cell above it. Clamped, because rounding may put a circle touching the wall
  // a hair outside [-R, R].
  int index(double x) const {
    const double u = std::floor((x + R_) / size_);
    return static_cast<int>(std::clamp(u, 0.0, static_cast<double>(across_ - 1)));
  }

  // Time for a circle starting at x (at time 0) with speed w along an axis to reach the face of
  // cell `cell` it moves towards; never for w = 0 or when that face is the grid's edge. Measured
  // in cell units from the same start, so the times of successive crossings only grow.
  double crossing_time(double x, double w, int cell) const {
    if (w == 0) return kNever;
    const int next = w > 0 ? cell + 1 : cell - 1;
    if (next < 0 || next >= across_) return kNever;  // the table's wall comes first
    const double face = w > 0 ? cell + 1 : cell;     // in cell units
    return std::max((face - (x + R_) / size_) * size_ / w, 0.0);
  }

  std::vector<int>& at(int ix, int iy) { return cells_[key(ix, iy)]; }
  const std::vector<int>* find(int ix, int iy) const {
    if (ix < 0 || iy < 0 || ix >= across_ || iy >= across_) return nullptr;
    const auto found = cells_.find(key(ix, iy));
    return found == cells_.end() ? nullptr : &found->second;
  }
  void remove(int ix, int iy, int circle) {
    std::vector<int>& cell = at(ix, iy);
    cell.erase(std::find(cell.begin(), cell.end(), circle));
  }

 private:
  long long key(int ix, int iy) const { return static_cast<long long>(ix) * across_ + iy; }
  double R_, size_;
  int across_;
  std::unordered_map<long long, std::vector<int>> cells_;
};

}  // namespace

Collision propagate_sectors(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                            Velocities& velocities, double cell_size) {
  checks::table(table_radius, circle_radius, n);
  checks::rows(coordinates, n, "coordinates");
  checks::rows(velocities, n, "velocities");
  checks::cell_size(table_radius, circle_radius, cell_size);
  checks::placement(table_radius, circle_radius, coordinates);

  const double reach = table_radius - circle_radius;
  Collision next{kNever, -1, kWall};
  // Every candidate goes through here, so an earlier time found once is never lost.
  const auto consider = [&](double t, int i, int other) {
    if (t < next.time) next = {t, i, other};
  };
  const auto test_pair = [&](int i, int j) {
    if (i != j) consider(pair_time(circle_radius, coordinates, velocities, i, j), std::min(i, j), std::max(i, j));
  };

  // 1. Cells, wall times, pairs in neighbouring cells, first crossings.
  Grid grid(table_radius, cell_size);
  std::vector<int> cx(static_cast<std::size_t>(n)), cy(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    cx[static_cast<std::size_t>(i)] = grid.index(coordinates(i, 0));
    cy[static_cast<std::size_t>(i)] = grid.index(coordinates(i, 1));
    grid.at(cx[static_cast<std::size_t>(i)], cy[static_cast<std::size_t>(i)]).push_back(i);
  }
  std::priority_queue<Crossing, std::vector<Crossing>, std::greater<>> crossings;
  const auto schedule = [&](int i) {
    const auto k = static_cast<std::size_t>(i);
    const double tx = grid.crossing_time(coordinates(i, 0), velocities(i, 0), cx[k]);
    const double ty = grid.crossing_time(coordinates(i, 1), velocities(i, 1), cy[k]);
    // At a corner both times are equal: x goes first, then y at the same time.
    if (tx <= ty && tx < kNever) crossings.push({tx, i, 0});
    else if (ty < kNever) crossings.push({ty, i, 1});
  };
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    consider(time_to_wall(coordinates.row(i), velocities.row(i), reach), i, kWall);
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        if (const std::vector<int>* cell = grid.find(cx[k] + dx, cy[k] + dy)) {
          for (const int j : *cell) {
            if (j > i) test_pair(i, j);  // each pair once
          }
        }
      }
    }
    schedule(i);
  }

  // 2. Crossings before the earliest collision found so far: it is not certain yet, since a
  // circle entering a new cell may meet a new neighbour earlier.
  while (!crossings.empty() && crossings.top().time < next.time) {
    const Crossing c = crossings.top();
    crossings.pop();
    const auto k = static_cast<std::size_t>(c.circle);
    const int step = velocities(c.circle, c.axis) > 0 ? 1 : -1;
    grid.remove(cx[k], cy[k], c.circle);
    (c.axis == 0 ? cx[k] : cy[k]) += step;
    grid.at(cx[k], cy[k]).push_back(c.circle);
    // The row (or column) of three cells beyond the new cell has just become neighbouring.
    for (int side = -1; side <= 1; ++side) {
      const int ix = c.axis == 0 ? cx[k] + step : cx[k] + side;
      const int iy = c.axis == 0 ? cy[k] + side : cy[k] + step;
      if (const std::vector<int>* cell = grid.find(ix, iy)) {
        for (const int j : *cell) test_pair(c.circle, j);
      }
    }
    schedule(c.circle);
  }
  if (next.time == kNever) {
    throw std::invalid_argument(n == 0 ? "n = 0: with no circles there is no collision to propagate to"
                                       : "velocities: all circles are at rest, so no collision will ever happen");
  }

  // 3. Move everything and collide, exactly as in propagate.
  coordinates += next.time * velocities;
  const int i = next.circle;
  if (next.other == kWall) {
    const Vector normal = coordinates.row(i).normalized();
    velocities.row(i) -= 2 * velocities.row(i).dot(normal) * normal;
  } else {
    const int j = next.other;
    const Vector normal = (coordinates.row(j) - coordinates.row(i)).normalized();
    const Vector exchange = (velocities.row(i) - velocities.row(j)).dot(normal) * normal;
    velocities.row(i) -= exchange;
    velocities.row(j) += exchange;
  }
  return next;
}

}  // namespace billiard
