#include "stages.hpp"

#include "billiard/argument_checks.hpp"
#include "billiard/table_svg.hpp"
#include "cli_text.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

namespace billiard_cli {

using billiard::Coordinates;
using billiard::Vector;
using billiard::Velocities;
using billiard::Wall;

int task_number(Stage stage) {
  switch (stage) {
    case Stage::Gravity: return 7;
    case Stage::Walls: return 8;
    case Stage::Sectors: return 9;
    case Stage::None: break;
  }
  return 0;
}

const char* stage_name(Stage stage) {
  switch (stage) {
    case Stage::Gravity: return "gravity";
    case Stage::Walls: return "walls";
    case Stage::Sectors: return "sectors";
    case Stage::None: break;
  }
  return "";
}

bool stage_built(Stage stage) {
  switch (stage) {
#ifdef BILLIARD_WITH_GRAVITY
    case Stage::Gravity: return true;
#endif
#ifdef BILLIARD_WITH_WALLS
    case Stage::Walls: return true;
#endif
#ifdef BILLIARD_WITH_SECTORS
    case Stage::Sectors: return true;
#endif
    default: return false;
  }
}

Vector parse_gravity(std::string_view value) {
  const auto comma = value.find(',');
  double gx = 0, gy = 0;
  if (comma == std::string_view::npos || !read_number(value.substr(0, comma), gx) ||
      !read_number(value.substr(comma + 1), gy) || std::abs(gx) > kMaxGravity || std::abs(gy) > kMaxGravity) {
    throw BadInput(text("--gravity must be two numbers GX,GY (each from -", kMaxGravity, " to ", kMaxGravity,
                        "), for example --gravity 0,-1, got ", in_quotes(value)));
  }
  return Vector(gx, gy);
}

std::vector<Wall> read_walls(const std::filesystem::path& file, double table_radius) {
  const std::string shown = in_quotes(file.string());
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) {
    throw BadInput(text("--walls ", shown, ": no such file; give a text file with one wall per line, AX AY BX BY"));
  }
  std::ifstream in(file);
  if (!in) throw BadInput(text("--walls ", shown, ": cannot read it; check its permissions"));
  std::vector<Wall> walls;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream words(line);
    std::vector<std::string> parts;
    for (std::string word; words >> word;) parts.push_back(word);
    double values[4] = {};
    bool numbers = parts.size() == 4;
    for (std::size_t k = 0; numbers && k < 4; ++k) numbers = read_number(parts[k], values[k]);
    if (!numbers) {
      throw BadInput(text("--walls ", shown, " line ", number, ": expected four numbers AX AY BX BY (a wall from (AX, AY) to (BX, BY)), got ",
                          in_quotes(line)));
    }
    const Wall wall{Vector(values[0], values[1]), Vector(values[2], values[3])};
    for (const Vector& end : {wall.a, wall.b}) {
      if (end.norm() > table_radius) {
        throw BadInput(text("--walls ", shown, " line ", number, ": the end point (", end(0), ", ", end(1),
                            ") is outside the table of radius ", table_radius, "; keep both ends within it"));
      }
    }
    if (walls.size() == std::size_t(kMaxWalls)) {
      throw BadInput(text("--walls ", shown, " line ", number, ": more than ", kMaxWalls, " walls; use fewer"));
    }
    walls.push_back(wall);
  }
  return walls;
}

int place_clear_of_walls(double table_radius, double circle_radius, Coordinates& coordinates,
                         const std::vector<Wall>& walls, billiard::Rng& rng) {
  const auto clear = [&](const Vector& p, Eigen::Index self) {
    for (const Wall& wall : walls) {
      if (billiard::checks::distance_to_wall(p, wall) < circle_radius * (1 + 1e-6)) return false;
    }
    for (Eigen::Index j = 0; j < coordinates.rows(); ++j) {
      if (j != self && (coordinates.row(j) - p).norm() < 2 * circle_radius * (1 + 1e-6)) return false;
    }
    return true;
  };
  const double reach = table_radius - circle_radius;
  std::uniform_real_distribution<double> uniform(-reach, reach);
  int moved = 0;
  for (Eigen::Index i = 0; i < coordinates.rows(); ++i) {
    if (clear(coordinates.row(i), i)) continue;
    bool placed = false;
    for (int attempt = 0; attempt < 100'000 && !placed; ++attempt) {
      const Vector p(uniform(rng), uniform(rng));
      if (p.norm() <= reach && clear(p, i)) {
        coordinates.row(i) = p;
        placed = true;
      }
    }
    if (!placed) {
      throw BadInput(text("the ", coordinates.rows(), " circles do not fit between the walls: circle ", i,
                          " found no free place; use fewer or smaller circles, or fewer walls"));
    }
    ++moved;
  }
  return moved;
}

billiard::Collision stage_step(const StageOptions& options, double table_radius, double circle_radius, int n,
                               Coordinates& coordinates, Velocities& velocities) {
  switch (options.stage) {
#ifdef BILLIARD_WITH_GRAVITY
    case Stage::Gravity:
      return billiard::propagate_gravity(table_radius, circle_radius, n, coordinates, velocities, options.gravity);
#endif
#ifdef BILLIARD_WITH_WALLS
    case Stage::Walls:
      return billiard::propagate_walls(table_radius, circle_radius, n, coordinates, velocities, options.walls);
#endif
#ifdef BILLIARD_WITH_SECTORS
    case Stage::Sectors:
      return billiard::propagate_sectors(table_radius, circle_radius, n, coordinates, velocities, options.cell_size);
#endif
    default: break;
  }
  (void)table_radius, (void)circle_radius, (void)n, (void)coordinates, (void)velocities;  // no stage built
  throw std::logic_error(text("stage ", stage_name(options.stage), " is not built"));
}

StageMovie::StageMovie(double table_radius, double circle_radius, const Coordinates& start)
    : table_radius_(table_radius), circle_radius_(circle_radius), times_{0.0}, frames_{start} {}

void StageMovie::flight(const Coordinates& before, const Velocities& velocities, const Vector& g, double time,
                        const Coordinates& after) {
  const double start = times_.back();
  if (g.squaredNorm() > 0) {
    for (int k = 1; k < kSamplesPerParabola; ++k) {
      const double t = time * k / kSamplesPerParabola;
      Coordinates sample = before + t * velocities;
      sample.rowwise() += 0.5 * t * t * g;
      frames_.push_back(sample);
      times_.push_back(start + t);
    }
  }
  frames_.push_back(after);
  times_.push_back(start + time);
}

void StageMovie::write(const std::filesystem::path& file, const std::vector<Wall>& walls) const {
  const double total = times_.back();
  std::ostringstream key_times;
  key_times.precision(10);
  for (std::size_t k = 0; k < times_.size(); ++k) {
    key_times << (k ? ";" : "") << (total > 0 ? times_[k] / total : double(k) / double(std::max<std::size_t>(times_.size() - 1, 1)));
  }
  // Playback: about 10 seconds for the whole run, at least 1 second.
  const double seconds = std::clamp(10.0 * double(times_.size()) / 200.0, 1.0, 60.0);
  billiard::TableSvg picture(table_radius_);
  picture.title(text(frames_.front().rows(), " circles, simulated time ", total));
  picture.table();
  for (const Wall& wall : walls) picture.wall(wall);
  const std::string style = text("fill=\"", billiard::TableSvg::kCircleFill, "\" stroke=\"#212121\" stroke-width=\"",
                                 0.05 * circle_radius_, "\"");
  for (Eigen::Index i = 0; i < frames_.front().rows(); ++i) {
    std::ostringstream animations;
    animations.precision(8);
    if (frames_.size() > 1) {
      for (const auto& [attribute, column] : {std::pair{"cx", 0}, std::pair{"cy", 1}}) {
        animations << "\n    <animate attributeName=\"" << attribute << "\" dur=\"" << seconds
                   << "s\" repeatCount=\"indefinite\" calcMode=\"linear\" keyTimes=\"" << key_times.str() << "\" values=\"";
        for (std::size_t k = 0; k < frames_.size(); ++k) {
          const double value = frames_[k](i, column);
          animations << (k ? ";" : "") << (column == 0 ? value : billiard::TableSvg::svg_y(value));
        }
        animations << "\"/>";
      }
      animations << "\n  ";
    }
    picture.circle(frames_.front().row(i), circle_radius_, style, animations.str());
  }
  std::ofstream svg(file);
  if (!svg) throw std::runtime_error(text("cannot write ", printable(file.string())));
  svg << picture.str();
  if (!svg.flush()) throw std::runtime_error(text("writing ", printable(file.string()), " failed"));
}

}  // namespace billiard_cli
