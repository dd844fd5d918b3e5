// An independent implementation of the "Collisions" exercise, written the exercise's way, to
// test the `particles` command against: an array of all N(N+1)/2 potential collisions (the
// earliest wall of each particle, and each pair), kept sorted by time; after each collision
// the entries of the particles involved are recomputed and put back in order.
#pragma once

#include <string>
#include <vector>

namespace particles_reference {

struct Particle {
  double x = 0, y = 0, u = 0, v = 0;
};

struct Box {
  double radius = 1, lx = 10, ly = 10;
  std::vector<Particle> particles;
};

struct Result {
  std::string output;              // the lines printf("%.6f, %.6f, %d, %d\n") prints
  std::vector<double> event_times; // the time of every collision processed, in order
};

// Runs to end_time (a collision at end_time exactly is processed), or until max_events
// collisions when max_events >= 0. physical: exchange only the normal components.
Result run(const Box& box, double end_time, bool physical = false, long max_events = -1);

// The text of an input file for `box`, numbers written with 17 significant digits.
std::string file_text(const Box& box);

}  // namespace particles_reference
