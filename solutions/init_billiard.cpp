// Task 1, reference solution: random, non-overlapping circles inside the table.
//
// A circle of radius a is fully inside the table of radius R when its centre is within
// R - a of the origin, and two circles do not overlap when their centres are at least 2a
// apart. We place the circles in two steps:
//
//  1. Placement. Try random sequential addition: draw a uniformly random centre in the
//     allowed disc and keep it if it overlaps no circle placed before; repeat. This is the
//     natural method and works well for dilute tables, but near an area fraction of about 0.5
//     almost every try fails (the free space left over shrinks to tiny gaps), so we give each
//     circle a budget of tries. If the budget runs out we start over from a hexagonal lattice,
//     the densest arrangement of equal circles, spread as wide as the table allows, and use n
//     of its sites chosen at random.
//  2. Shaking. Monte Carlo moves: pick a random circle, propose a small random displacement,
//     accept it if the circle stays inside and overlaps nobody. These moves treat every
//     allowed table alike (detailed balance), so after enough of them the lattice is
//     forgotten and the table is a random sample of all allowed tables.
//
// Overlap tests use a grid of square cells at least one diameter wide: a circle can only
// overlap circles in its own cell and the 8 around it, so each test costs O(1) instead of
// O(n), and init_billiard stays fast for thousands of circles.
#include "billiard/argument_checks.hpp"
#include "billiard/course.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace billiard {
namespace {

// The densest packing of equal circles in the plane, the hexagonal one, covers pi/sqrt(12)
// of the area; no arrangement inside a bounded table can do better.
constexpr double kDensestPacking = 0.9068996821171089;
constexpr int kTriesPerCircle = 2000;  // random sequential addition budget, per circle
constexpr int kShakeSweeps = 200;      // Monte Carlo moves per circle

// Square cells of side >= 2a covering [-reach, reach]^2; each cell lists its circles.
class Grid {
 public:
  Grid(double reach, double diameter, int n) : reach_(reach), diameter_(diameter) {
    // Cells at least a diameter wide, and not many more cells than circles.
    const int by_size = static_cast<int>(2 * reach / diameter);
    const int by_count = 2 * static_cast<int>(std::ceil(std::sqrt(double(n)))) + 1;
    side_ = std::max(1, std::min(by_size, by_count));
    cell_width_ = 2 * reach / side_;
    cells_.resize(std::size_t(side_) * side_);
  }

  void insert(int i, const Vector& p) { cells_[cell_of(p)].push_back(i); }

  void remove(int i, const Vector& p) {
    auto& cell = cells_[cell_of(p)];
    cell.erase(std::find(cell.begin(), cell.end(), i));
  }

  // True if a circle centred at p would overlap a listed circle other than `ignore`.
  bool overlaps(const Vector& p, const Coordinates& centres, int ignore) const {
    const int cx = column_of(p(0)), cy = column_of(p(1));
    for (int gx = std::max(cx - 1, 0); gx <= std::min(cx + 1, side_ - 1); ++gx) {
      for (int gy = std::max(cy - 1, 0); gy <= std::min(cy + 1, side_ - 1); ++gy) {
        for (int j : cells_[std::size_t(gx) * side_ + gy]) {
          if (j != ignore && (centres.row(j) - p).squaredNorm() < diameter_ * diameter_) return true;
        }
      }
    }
    return false;
  }

 private:
  int column_of(double x) const { return std::clamp(static_cast<int>((x + reach_) / cell_width_), 0, side_ - 1); }
  std::size_t cell_of(const Vector& p) const {
    return std::size_t(column_of(p(0))) * side_ + column_of(p(1));
  }

  double reach_, diameter_, cell_width_;
  int side_;
  std::vector<std::vector<int>> cells_;
};

// Uniformly random point in the disc of radius `reach` (rejection from the square around it).
Vector random_point_in_disc(double reach, Rng& rng) {
  std::uniform_real_distribution<double> coordinate(-reach, reach);
  for (;;) {
    const Vector p(coordinate(rng), coordinate(rng));
    if (p.squaredNorm() <= reach * reach) return p;  // accepted with probability pi/4
  }
}

// Random sequential addition; false if some circle found no free spot within its budget.
bool place_one_by_one(double reach, Grid& grid, Coordinates& centres, Rng& rng) {
  for (int i = 0; i < centres.rows(); ++i) {
    int tries = 0;
    Vector p;
    do {
      if (++tries > kTriesPerCircle) return false;
      p = random_point_in_disc(reach, rng);
    } while (grid.overlaps(p, centres, -1));
    centres.row(i) = p;
    grid.insert(i, p);
  }
  return true;
}

// Sites of a hexagonal lattice with the given spacing, within `reach` of the origin.
std::vector<Vector> lattice_sites(double spacing, double reach) {
  std::vector<Vector> sites;
  const double row_height = spacing * std::sqrt(3.0) / 2;
  const int rows = static_cast<int>(reach / row_height);
  for (int r = -rows; r <= rows; ++r) {
    const double shift = (r % 2 == 0) ? 0.0 : spacing / 2;  // every other row is offset
    const int columns = static_cast<int>(reach / spacing) + 1;
    for (int c = -columns; c <= columns; ++c) {
      const Vector p(c * spacing + shift, r * row_height);
      if (p.squaredNorm() <= reach * reach) sites.push_back(p);
    }
  }
  return sites;
}

// n random sites of the widest hexagonal lattice that still has n sites inside the table.
bool place_on_lattice(double reach, double diameter, Grid& grid, Coordinates& centres, Rng& rng) {
  const auto n = static_cast<std::size_t>(centres.rows());
  if (lattice_sites(diameter, reach).size() < n) return false;
  double tight = diameter, loose = 2 * reach + diameter;  // lattice_sites(loose) has one site
  for (int step = 0; step < 50; ++step) {                 // bisection on the spacing
    const double middle = 0.5 * (tight + loose);
    (lattice_sites(middle, reach).size() >= n ? tight : loose) = middle;
  }
  auto sites = lattice_sites(tight, reach);
  std::shuffle(sites.begin(), sites.end(), rng);
  for (std::size_t i = 0; i < n; ++i) {
    centres.row(Eigen::Index(i)) = sites[i];
    grid.insert(int(i), sites[i]);
  }
  return true;
}

// Monte Carlo shaking. During the first half of the sweeps the step size is tuned towards
// about half of the moves accepted; then it is frozen. (A step size that keeps changing with
// the state would break detailed balance and favour some tables, e.g. circles near the wall.)
void shake(double reach, double circle_radius, Grid& grid, Coordinates& centres, Rng& rng) {
  const int n = static_cast<int>(centres.rows());
  if (n == 0) return;
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double step = circle_radius;
  for (int sweep = 0; sweep < kShakeSweeps; ++sweep) {
    int accepted = 0;
    for (int move = 0; move < n; ++move) {
      const int i = pick(rng);
      const Vector old = centres.row(i);
      const Vector proposal = old + step * Vector(unit(rng), unit(rng));
      if (proposal.squaredNorm() > reach * reach || grid.overlaps(proposal, centres, i)) continue;
      grid.remove(i, old);
      centres.row(i) = proposal;
      grid.insert(i, proposal);
      ++accepted;
    }
    if (sweep < kShakeSweeps / 2) step = std::min(step * ((2 * accepted > n) ? 1.2 : 0.8), 2 * reach);
  }
}

}  // namespace

Coordinates init_billiard(double table_radius, double circle_radius, int n, Rng& rng) {
  checks::table(table_radius, circle_radius, n);
  const double area_fraction = n * (circle_radius / table_radius) * (circle_radius / table_radius);
  if (area_fraction > kDensestPacking) {
    std::ostringstream message;
    message.precision(4);
    message << "n = " << n << ": " << n << " circles of radius " << circle_radius
            << " cannot fit on a table of radius " << table_radius << ": their area is " << area_fraction
            << " times the table's, and no arrangement covers more than " << kDensestPacking
            << " of it; use fewer or smaller circles";
    throw std::invalid_argument(message.str());
  }

  const double reach = table_radius - circle_radius;  // centres stay within this distance of 0
  const double diameter = 2 * circle_radius;
  Coordinates centres(n, 2);
  Grid grid(reach, diameter, n);
  if (!place_one_by_one(reach, grid, centres, rng)) {
    grid = Grid(reach, diameter, n);
    if (!place_on_lattice(reach, diameter, grid, centres, rng)) {
      std::ostringstream message;
      message.precision(4);
      message << "n = " << n << ": could not place " << n << " circles of radius " << circle_radius
              << " on a table of radius " << table_radius << " (area fraction " << area_fraction
              << "; even a hexagonal arrangement does not fit them): use fewer or smaller circles";
      throw std::invalid_argument(message.str());
    }
  }
  shake(reach, circle_radius, grid, centres, rng);
  return centres;
}

}  // namespace billiard
