// The extension stages in the `billiard` command (tasks 7-9, billiard/extensions.hpp): their
// options, the walls file, and the movie the command draws of a stage's run (a stage has no
// movie function of its own: the command samples the flights between events, the parabolas
// under gravity included, and draws the walls).
#pragma once

#include "billiard/extensions.hpp"

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace billiard_cli {

enum class Stage { None, Gravity, Walls, Sectors };

// The task number and the name of a stage (7 "gravity", ...).
int task_number(Stage stage);
const char* stage_name(Stage stage);
// Whether this build has the stage (tests/grader/course.txt may switch it off).
bool stage_built(Stage stage);

struct StageOptions {
  Stage stage = Stage::None;
  billiard::Vector gravity = billiard::Vector::Zero();
  std::filesystem::path walls_file;
  std::vector<billiard::Wall> walls;  // read from walls_file once the table radius is known
  double cell_size = 0;
};

// Limits of the stages' options (see billiard --help).
inline constexpr double kMaxGravity = 1000;
inline constexpr int kMaxWalls = 1000;

// "--gravity GX,GY": two numbers, each of magnitude at most kMaxGravity. Throws BadInput.
billiard::Vector parse_gravity(std::string_view value);

// A walls file: one wall per line, "AX AY BX BY" (its end points), blank lines and lines
// starting with # ignored. Throws BadInput naming the line for anything else, and for end
// points outside the table.
std::vector<billiard::Wall> read_walls(const std::filesystem::path& file, double table_radius);

// Moves every circle that overlaps a wall to a random free place on the table (drawn from rng,
// so the same seed gives the same table); returns how many moved. Throws BadInput when no free
// place is found: the circles do not fit between the walls.
int place_clear_of_walls(double table_radius, double circle_radius, billiard::Coordinates& coordinates,
                         const std::vector<billiard::Wall>& walls, billiard::Rng& rng);

// One event of the stage, through the student's (or the reference) function.
billiard::Collision stage_step(const StageOptions& options, double table_radius, double circle_radius, int n,
                               billiard::Coordinates& coordinates, billiard::Velocities& velocities);

// An animated SVG of a stage's run: key frames at every event and, under gravity, samples
// along each parabola in between (motion is linear between key frames in SMIL).
class StageMovie {
 public:
  StageMovie(double table_radius, double circle_radius, const billiard::Coordinates& start);
  // Records the flight from `coordinates`, `velocities` (before the step) lasting `time`, and the
  // state after it.
  void flight(const billiard::Coordinates& before, const billiard::Velocities& velocities, const billiard::Vector& g,
              double time, const billiard::Coordinates& after);
  void write(const std::filesystem::path& file, const std::vector<billiard::Wall>& walls) const;
  // Samples per flight under gravity (its parabola drawn as this many straight pieces).
  static constexpr int kSamplesPerParabola = 8;

 private:
  double table_radius_, circle_radius_;
  std::vector<double> times_;
  std::vector<billiard::Coordinates> frames_;
};

}  // namespace billiard_cli
