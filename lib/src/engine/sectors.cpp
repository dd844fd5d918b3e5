// Sectors: the uniform grid of cells. See sectors.hpp.
#include "sectors.hpp"
#include "wall_geometry.hpp"

#include <algorithm>
#include <cmath>

namespace billiard {

Grid make_grid(const Vector& lower, const Vector& extent, double min_cell, bool periodic) {
  Grid grid;
  grid.lower = lower;
  grid.extent = extent;
  grid.periodic = periodic;
  auto count = [&](double length) {
    // As many cells as fit with side >= min_cell, capped so that a tiny min_cell cannot ask for
    // billions of cells (the cap keeps memory linear; cells are then just larger than needed).
    double n = std::floor(length / min_cell);
    n = std::clamp(n, 1.0, 65535.0);  // (HotDisc keeps a cell's column and row in 16 bits)
    return static_cast<int>(n);
  };
  grid.nx = count(extent.x());
  grid.ny = count(extent.y());
  grid.cell = Vector(extent.x() / grid.nx, extent.y() / grid.ny);
  grid.capacity = kInline + 1;
  grid.records.assign(static_cast<std::size_t>(grid.nx) * grid.ny * 4, kNoDisc);
  for (std::size_t c = 0; c < grid.records.size(); c += 4) grid.records[c] = 0;
  grid.wall_ranges.assign(2 * static_cast<std::size_t>(grid.nx) * grid.ny, 0);
  return grid;
}

int capacity_for(const Grid& grid, double min_radius) {
  const double densest = M_PI / (2 * std::sqrt(3.0));
  const double w = grid.cell.x() + 2 * min_radius;
  const double h = grid.cell.y() + 2 * min_radius;
  const double bound = densest * w * h / (M_PI * min_radius * min_radius);
  return static_cast<int>(std::min(bound, 1.0e6)) + 1;
}

void set_capacity(Grid& grid, int capacity) {
  capacity = std::max(capacity, kInline + 1);
  if (capacity == grid.capacity) return;
  // Move every spilled cell's discs to a block of the new size.
  BigVector<int> spill;
  const std::size_t cells = grid.records.size() / 4;
  for (std::size_t c = 0; c < cells; ++c) {
    int* record = &grid.records[c * 4];
    const int count = record[0] & (kHasWalls - 1);
    if (count <= kInline) continue;
    const std::size_t offset = spill.size();
    spill.resize(offset + capacity, kNoDisc);
    std::copy_n(&grid.spill[static_cast<std::size_t>(record[1])], count, &spill[offset]);
    record[1] = static_cast<int>(offset);
  }
  grid.spill.swap(spill);
  grid.spill_free.clear();
  grid.capacity = capacity;
}

void insert_disc(Grid& grid, int c, int i) {
  if (cell_disc_count(grid, c) == grid.capacity) set_capacity(grid, 2 * grid.capacity);
  int* record = &grid.records[static_cast<std::size_t>(c) * 4];
  const int count = record[0] & (kHasWalls - 1);
  if (count < kInline) {
    record[1 + count] = i;
  } else if (count == kInline) {
    // The fourth disc: move the cell's discs to a spill block.
    int offset;
    if (!grid.spill_free.empty()) {
      offset = grid.spill_free.back();
      grid.spill_free.pop_back();
    } else {
      offset = static_cast<int>(grid.spill.size());
      grid.spill.resize(grid.spill.size() + grid.capacity, kNoDisc);
    }
    int* block = &grid.spill[static_cast<std::size_t>(offset)];
    std::copy_n(record + 1, kInline, block);
    block[kInline] = i;
    record[1] = offset;
    record[2] = record[3] = kNoDisc;
  } else {
    grid.spill[static_cast<std::size_t>(record[1]) + count] = i;
  }
  ++record[0];
}

void remove_disc(Grid& grid, int c, int i) {
  int* record = &grid.records[static_cast<std::size_t>(c) * 4];
  const int count = record[0] & (kHasWalls - 1);
  int* items = count <= kInline ? record + 1 : &grid.spill[static_cast<std::size_t>(record[1])];
  const int last = count - 1;
  for (int k = 0; k < last; ++k) {
    if (items[k] == i) {
      items[k] = items[last];
      break;
    }
  }
  items[last] = kNoDisc;
  --record[0];
  if (count == kInline + 1) {
    // Back to kInline discs: into the record again, the block freed.
    const int offset = record[1];
    std::copy_n(items, kInline, record + 1);
    grid.spill_free.push_back(offset);
  }
}

int cell_of(const Grid& grid, const Vector& p) {
  const int cx = std::clamp(static_cast<int>(std::floor((p.x() - grid.lower.x()) / grid.cell.x())), 0, grid.nx - 1);
  const int cy = std::clamp(static_cast<int>(std::floor((p.y() - grid.lower.y()) / grid.cell.y())), 0, grid.ny - 1);
  return cx + grid.nx * cy;
}

void cell_bounds(const Grid& grid, int c, Vector& lo, Vector& hi) {
  const int cx = c % grid.nx;
  const int cy = c / grid.nx;
  lo = Vector(grid.lower.x() + cx * grid.cell.x(), grid.lower.y() + cy * grid.cell.y());
  hi = Vector(grid.lower.x() + (cx + 1) * grid.cell.x(), grid.lower.y() + (cy + 1) * grid.cell.y());
  if (cx == grid.nx - 1) hi.x() = grid.periodic ? grid.lower.x() + grid.extent.x() : kNever;
  if (cy == grid.ny - 1) hi.y() = grid.periodic ? grid.lower.y() + grid.extent.y() : kNever;
  if (!grid.periodic) {
    if (cx == 0) lo.x() = -kNever;
    if (cy == 0) lo.y() = -kNever;
  }
}

void assign_walls(Grid& grid, const std::vector<WallShape>& walls, double reach) {
  const int cells = grid.nx * grid.ny;
  std::vector<std::vector<int>> lists(static_cast<std::size_t>(cells));
  for (int k = 0; k < static_cast<int>(walls.size()); ++k) {
    const WallShape& wall = walls[k];
    // Only the cells of the wall's bounding box grown by `reach` can be near it.
    Vector box_lo, box_hi;
    if (wall.kind == WallKind::Arc) {
      arc_bounds(wall, box_lo, box_hi);
      box_lo -= Vector::Constant(reach);
      box_hi += Vector::Constant(reach);
    } else if (wall.kind == WallKind::Circle) {
      box_lo = wall.a - Vector::Constant(wall.radius + reach);
      box_hi = wall.a + Vector::Constant(wall.radius + reach);
    } else {
      const Vector b = wall.kind == WallKind::Segment ? wall.b : wall.a;
      box_lo = wall.a.cwiseMin(b) - Vector::Constant(reach);
      box_hi = wall.a.cwiseMax(b) + Vector::Constant(reach);
    }
    const int c_lo = cell_of(grid, box_lo);
    const int c_hi = cell_of(grid, box_hi);
    for (int cy = c_lo / grid.nx; cy <= c_hi / grid.nx; ++cy) {
      for (int cx = c_lo % grid.nx; cx <= c_hi % grid.nx; ++cx) {
        const Vector lo(grid.lower.x() + cx * grid.cell.x(), grid.lower.y() + cy * grid.cell.y());
        const Vector hi = lo + grid.cell;
        bool near = false;
        switch (wall.kind) {
          case WallKind::Segment:
            near = segment_rectangle_distance(wall.a, wall.b, lo, hi) <= reach;
            break;
          case WallKind::Point:
            near = point_rectangle_distance(wall.a, lo, hi) <= reach;
            break;
          case WallKind::Arc:
            near = arc_rectangle_distance(wall, lo, hi) <= reach;
            break;
          case WallKind::Circle: {
            // A disc of radius <= reach centred in the cell can touch the rim only if the cell
            // reaches out to distance radius - reach from the centre.
            const Vector far = (lo - wall.a).cwiseAbs().cwiseMax((hi - wall.a).cwiseAbs());
            near = far.norm() >= wall.radius - reach;
            break;
          }
        }
        if (near) lists[cx + grid.nx * cy].push_back(k);
      }
    }
  }
  grid.wall_items.clear();
  for (int c = 0; c < cells; ++c) {
    grid.wall_ranges[2 * static_cast<std::size_t>(c)] = static_cast<int>(grid.wall_items.size());
    grid.wall_items.insert(grid.wall_items.end(), lists[c].begin(), lists[c].end());
    grid.wall_ranges[2 * static_cast<std::size_t>(c) + 1] = static_cast<int>(grid.wall_items.size());
    int& head = grid.records[static_cast<std::size_t>(c) * 4];
    head = lists[c].empty() ? (head & ~kHasWalls) : (head | kHasWalls);
  }
}

}  // namespace billiard
