// Sectors (cells): a uniform grid over the container. A disc is listed in the cell holding its
// centre; two discs can touch only if their cells are neighbours (cells are at least one
// largest diameter wide), and a disc can touch a wall only if that wall is listed in the disc's
// own cell (each cell lists the walls within one largest radius of it). Leaving a cell is an
// event (EventKind::CellCrossing). Periodic grids wrap around.
#pragma once

#include "billiard/memory.hpp"
#include "billiard/vec2.hpp"
#include "billiard/wall.hpp"

#include <vector>

namespace billiard {

inline constexpr int kNoDisc = -1;

struct Grid {
  Vec2 lower = Vec2::Zero();  // corner of cell (0, 0)
  Vec2 extent = Vec2::Zero(); // size of the whole grid (the period when periodic)
  Vec2 cell = Vec2::Zero();   // size of one cell
  int nx = 1;
  int ny = 1;
  bool periodic = false;
  // One record of `stride` ints per cell: [disc count, first wall item, end of wall items,
  // disc indices (capacity slots)...]. Fixed-size slots instead of linked lists, so that the
  // loads of a cell's discs are independent (a linked list makes every load wait for the
  // previous one), and the count, the walls and the discs of a cell share one cache line (the
  // event loop is memory-bound from N ~ 10^5). capacity comes from the densest packing.
  int capacity = 1;
  int stride = 4;
  BigVector<int> records;       // nx*ny*stride
  std::vector<int> wall_items;  // wall indices, cell by cell
};

// A grid over [lower, lower + extent] with cells no smaller than min_cell (at least one per side;
// the caller keeps 3 per side in a periodic grid by its choice of min_cell). Cells are numbered
// c = cx + nx cy.
Grid make_grid(const Vec2& lower, const Vec2& extent, double min_cell, bool periodic);

// Most discs of radius >= min_radius whose centres can lie in one cell without overlapping:
// their areas fit in the cell grown by min_radius on every side at no more than the densest
// packing fraction pi / (2 sqrt 3), plus one for rounding.
int capacity_for(const Grid& grid, double min_radius);

inline int cell_disc_count(const Grid& grid, int c) { return grid.records[static_cast<std::size_t>(c) * grid.stride]; }
inline const int* cell_discs(const Grid& grid, int c) { return &grid.records[static_cast<std::size_t>(c) * grid.stride + 3]; }
inline int cell_walls_begin(const Grid& grid, int c) { return grid.records[static_cast<std::size_t>(c) * grid.stride + 1]; }
inline int cell_walls_end(const Grid& grid, int c) { return grid.records[static_cast<std::size_t>(c) * grid.stride + 2]; }

// Sets the slot count of every cell (keeps the discs and walls already listed).
void set_capacity(Grid& grid, int capacity);

// Adds disc i to cell c / removes it (growing the slots of every cell if one is full).
void insert_disc(Grid& grid, int c, int i);
void remove_disc(Grid& grid, int c, int i);

// Cell of a point (clamped to the grid; for a periodic grid the point must be inside the period).
int cell_of(const Grid& grid, const Vec2& p);

// Bounds of cell c used for crossing events. The outer faces of a non-periodic grid are at
// infinity: nothing can leave the grid, so rounding at the container's edge cannot lose a disc.
void cell_bounds(const Grid& grid, int c, Vec2& lo, Vec2& hi);

// Fills the wall ranges and wall_items: wall k is listed in every cell whose rectangle lies within
// `reach` (the largest disc radius, plus a margin) of it.
void assign_walls(Grid& grid, const std::vector<Wall>& walls, double reach);

}  // namespace billiard
