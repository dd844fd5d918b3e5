// Mutant of task movie: the key times are the individual collision times (time since the previous collision) instead of the running total.
// Expected: loses points in movie (e.g. Movie.AnimationShowsTheDiscsAtEveryCollision fails; 2 of 11 tests fail).
//
// Task 5, reference solution with the one bug above: an animated SVG of `collisions` events.
//
// Between two collisions every circle moves in a straight line at constant speed. An SVG
// <animate> element with linear interpolation between key frames shows exactly that motion if
// its key frames are the positions at the collisions and its keyTimes are the collision times
// as fractions of the whole run. So we record the table after every call to propagate and
// write one <animate> for cx and one for cy per circle. Browsers play it (SMIL animation).
#include "billiard/argument_checks.hpp"
#include "billiard/course.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <vector>

namespace billiard {
namespace {

// "v0;v1;v2;..." for one column of every frame of circle i (sign -1 flips y for SVG).
std::string frame_values(const std::vector<Coordinates>& frames, int i, int column, double sign) {
  std::ostringstream values;
  values.precision(8);
  for (std::size_t k = 0; k < frames.size(); ++k) values << (k ? ";" : "") << sign * frames[k](i, column);
  return values.str();
}

}  // namespace

void movie(double table_radius, double circle_radius, int n, Coordinates& coordinates,
           Velocities& velocities, int collisions, const std::filesystem::path& svg_file) {
  checks::table(table_radius, circle_radius, n);
  checks::rows(coordinates, n, "coordinates");
  checks::rows(velocities, n, "velocities");
  if (collisions < 0) {
    throw std::invalid_argument("collisions = " + std::to_string(collisions) + ": must be 0 or more");
  }

  // Key frames: the table now and after each collision, and the time of each frame.
  const double speed = std::sqrt(velocities.squaredNorm() / std::max(n, 1));  // rms speed, before
  std::vector<Coordinates> frames{coordinates};
  std::vector<double> times{0.0};
  for (int k = 0; k < collisions; ++k) {
    const Collision event = propagate(table_radius, circle_radius, n, coordinates, velocities);
    frames.push_back(coordinates);
    times.push_back(event.time);
  }
  double total_time = 0;
  for (const double t : times) total_time += t;

  // keyTimes run from 0 to 1 in proportion to simulated time. Playback speed: a circle at the
  // rms speed crosses the table in about 4 seconds.
  std::ostringstream key_times;
  key_times.precision(10);
  for (std::size_t k = 0; k < times.size(); ++k) {
    const double fraction = total_time > 0 ? times[k] / total_time : double(k) / double(times.size() - 1);
    key_times << (k ? ";" : "") << fraction;
  }
  const double seconds = std::max(1.0, 4.0 * total_time * speed / (2 * table_radius));

  // The picture is written as in visualize_table, plus the animations. (Each task's file
  // stands on its own, so that each task can be graded with the others' reference code.)
  std::ofstream svg(svg_file);
  if (!svg) throw std::runtime_error("svg_file = " + svg_file.string() + ": cannot open it for writing");
  svg.precision(10);
  const double margin = 0.05 * table_radius;
  const double corner = -table_radius - margin, size = 2 * (table_radius + margin);
  svg << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"600\" height=\"600\" viewBox=\"" << corner << ' '
      << corner << ' ' << size << ' ' << size << "\">\n"
      << "  <title>" << n << " circles, " << collisions << " collisions, simulated time " << total_time
      << "</title>\n"
      << "  <circle cx=\"0\" cy=\"0\" r=\"" << table_radius << "\" fill=\"#2e7d32\" stroke=\"#4e342e\" stroke-width=\""
      << 0.02 * table_radius << "\"/>\n";
  for (int i = 0; i < n; ++i) {
    svg << "  <circle cx=\"" << frames[0](i, 0) << "\" cy=\"" << -frames[0](i, 1) << "\" r=\"" << circle_radius
        << "\" fill=\"#fdd835\" stroke=\"#212121\" stroke-width=\"" << 0.05 * circle_radius << "\">";
    if (collisions > 0) {
      for (const auto& [attribute, column, sign] : {std::tuple{"cx", 0, 1.0}, std::tuple{"cy", 1, -1.0}}) {
        svg << "\n    <animate attributeName=\"" << attribute << "\" dur=\"" << seconds
            << "s\" repeatCount=\"indefinite\" calcMode=\"linear\" keyTimes=\"" << key_times.str() << "\" values=\""
            << frame_values(frames, i, column, sign) << "\"/>";
      }
      svg << "\n  ";
    }
    svg << "</circle>\n";
  }
  svg << "</svg>\n";
  if (!svg.flush()) throw std::runtime_error("svg_file = " + svg_file.string() + ": writing it failed");
}

}  // namespace billiard
