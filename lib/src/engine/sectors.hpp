// Sectors (cells): a uniform grid over the container. A disc is listed in the cell holding its
// centre; two discs can touch only if their cells are neighbours (cells are at least one
// largest diameter wide), and a disc can touch a wall only if that wall is listed in the disc's
// own cell (each cell lists the walls within one largest radius of it). Leaving a cell is an
// event of the loop (a crossing, see engine.cpp). Periodic grids wrap around.
#pragma once

#include "memory.hpp"
#include "billiard/engine/plane.hpp"
#include "billiard/engine/disc.hpp"  // kNoDisc
#include "billiard/engine/wall.hpp"

#include <vector>

namespace billiard {

struct Grid {
  Vector lower = Vector::Zero();  // corner of cell (0, 0)
  Vector extent = Vector::Zero(); // size of the whole grid (the period when periodic)
  Vector cell = Vector::Zero();   // size of one cell
  int nx = 1;
  int ny = 1;
  bool periodic = false;
  // One record of 4 ints (16 bytes, four cells to a cache line) per cell: [disc count, plus
  // kHasWalls if walls are listed in the cell; then up to kInline disc indices, or, when the
  // cell holds more, the offset of its block in `spill`]. The event loop is memory-bound from
  // N ~ 10^5 on and reads a 3 x 3 block of records per prediction: small records put a row of
  // three on one or two cache lines (64-byte records with room for more discs would make it
  // three). Cells with more than kInline discs are rare (about 0.7% at area
  // fraction 0.1 with the automatic cell size) and keep their discs in a block of `capacity`
  // slots in `spill`. Fixed-size slots instead of linked lists, so that the loads of a cell's
  // discs are independent.
  int capacity = 1;            // most discs one cell can hold (the size of a spill block)
  BigVector<int> records;      // 4 nx ny
  BigVector<int> spill;        // blocks of `capacity` slots
  std::vector<int> spill_free; // offsets of unused blocks
  std::vector<int> wall_ranges;  // per cell: first and end of its items in wall_items
  std::vector<int> wall_items;   // wall indices, cell by cell
};

inline constexpr int kInline = 3;
inline constexpr int kHasWalls = 1 << 30;

// A grid over [lower, lower + extent] with cells no smaller than min_cell (at least one per side;
// the caller keeps 3 per side in a periodic grid by its choice of min_cell). Cells are numbered
// c = cx + nx cy.
Grid make_grid(const Vector& lower, const Vector& extent, double min_cell, bool periodic);

// Most discs of radius >= min_radius whose centres can lie in one cell without overlapping:
// their areas fit in the cell grown by min_radius on every side at no more than the densest
// packing fraction pi / (2 sqrt 3), plus one for rounding.
int capacity_for(const Grid& grid, double min_radius);

inline int cell_disc_count(const Grid& grid, int c) {
  return grid.records[static_cast<std::size_t>(c) * 4] & (kHasWalls - 1);
}
inline bool cell_has_walls(const Grid& grid, int c) { return (grid.records[static_cast<std::size_t>(c) * 4] & kHasWalls) != 0; }
// The cell's discs: cell_disc_count(grid, c) indices.
inline const int* cell_discs(const Grid& grid, int c) {
  const int* record = &grid.records[static_cast<std::size_t>(c) * 4];
  return (record[0] & (kHasWalls - 1)) <= kInline ? record + 1 : &grid.spill[static_cast<std::size_t>(record[1])];
}
// Appends the discs of cell c to list[m...] and returns the new length. A cell of at most kInline
// discs (nearly all) has its three slots copied whatever its count and the length advanced by
// the count: a loop over the count (0 to 3 at random) mispredicts its exit most of the time
// (cachegrind: the largest source of mispredicted branches at low density). So `list` needs
// room for kInline entries beyond the discs it can receive.
inline int append_cell_discs(const Grid& grid, int c, int* list, int m) {
  static_assert(kInline == 3, "the inline copy below writes three slots");
  const int* record = &grid.records[static_cast<std::size_t>(c) * 4];
  const int count = record[0] & (kHasWalls - 1);
  if (count <= kInline) {
    list[m] = record[1];
    list[m + 1] = record[2];
    list[m + 2] = record[3];
  } else {
    const int* items = &grid.spill[static_cast<std::size_t>(record[1])];
    for (int k = 0; k < count; ++k) list[m + k] = items[k];
  }
  return m + count;
}
inline int cell_walls_begin(const Grid& grid, int c) { return grid.wall_ranges[2 * static_cast<std::size_t>(c)]; }
inline int cell_walls_end(const Grid& grid, int c) { return grid.wall_ranges[2 * static_cast<std::size_t>(c) + 1]; }

// Sets the most discs a cell can hold (keeps the discs already listed).
void set_capacity(Grid& grid, int capacity);

// Adds disc i to cell c / removes it (growing the capacity of every cell if one is full).
void insert_disc(Grid& grid, int c, int i);
void remove_disc(Grid& grid, int c, int i);

// Cell of a point (clamped to the grid; for a periodic grid the point must be inside the period).
int cell_of(const Grid& grid, const Vector& p);

// Bounds of cell c used for crossing events. The outer faces of a non-periodic grid are at
// infinity: nothing can leave the grid, so rounding at the container's edge cannot lose a disc.
void cell_bounds(const Grid& grid, int c, Vector& lo, Vector& hi);

// Fills the wall ranges and wall_items: wall k is listed in every cell whose rectangle lies within
// `reach` (the largest disc radius, plus a margin) of it.
void assign_walls(Grid& grid, const std::vector<WallShape>& walls, double reach);

}  // namespace billiard
