// The `particles` command: the classic "Collisions" exercise (particles FILE END_TIME) run on the
// event-driven engine. Reads N equal discs in a box, processes every collision up to END_TIME
// and prints, per particle, "x, y, wall collisions, particle collisions" as
// printf("%.6f, %.6f, %d, %d\n") does. Bad input: one line on stderr, exit 2, nothing on stdout.
#include "cli_text.hpp"

#include "billiard/engine/simulation.hpp"
#include "billiard/limits.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace {

using billiard_cli::BadInput;
using billiard_cli::in_quotes;
using billiard_cli::text;
using billiard_cli::thousands;

// Limits: every accepted run ends within a minute (the engine does about a million collisions
// per second here) and no number overflows.
constexpr long long kMaxParticles = 1000000;
constexpr std::int64_t kMaxCollisions = 20000000;
using billiard::limits::kRelativeRadius;   // radius >= 1e-6 max(Lx, Ly): the engine's precision
constexpr std::int64_t kEventsPerChunk = 1 << 16;  // events logged between two tallies

std::string help() {
  return text(R"(usage: particles [--physical] FILE END_TIME
       particles --help

Hard discs in a box, the "Collisions" exercise: every collision up to END_TIME is processed in
time order, then every particle is moved to END_TIME and one line per particle is printed, in
the file's order:  x, y, wall_collisions, particle_collisions  (printf "%.6f, %.6f, %d, %d").

FILE (plain text, numbers separated by spaces or tabs; CRLF line ends and blank lines at the
end are accepted):
  line 1      N, the number of particles (a whole number), numbered 0 to N-1
  line 2      their common radius R
  line 3      the box lengths Lx Ly: walls at x = 0, x = Lx, y = 0, y = Ly
  N lines     one per particle: x y u v (position and velocity)
Particles must lie inside the box, off the walls (R <= x <= Lx - R, R <= y <= Ly - R) and
must not overlap (centres at least 2R apart); touching is allowed.

rules:
  a particle hitting a wall reverses the velocity component normal to it; a particle meeting
  a corner hits both walls at the same instant: two wall collisions.
  default     two particles that meet exchange their whole velocities (the exercise's rule:
              exact for equal masses in head-on collisions; discs that are perfectly rough and
              never spin)
  --physical  they exchange only the components along the line of centres (smooth discs, the
              rest of this project); head-on collisions are the same under both rules.
  A collision at END_TIME exactly is processed.

limits (so that every run ends within a minute and no number overflows):
  0 <= N <= )", thousands(kMaxParticles), R"(; every number finite, at most 1e50 in magnitude
  R > 0, Lx > 0, Ly > 0, R >= 1e-6 max(Lx, Ly); END_TIME >= 0
  at most )", thousands(kMaxCollisions), R"( collisions before END_TIME (else exit 2: choose a smaller END_TIME)

exit status: 0 done; 1 unexpected failure; 2 bad input (one line on stderr naming the file
and line, nothing on stdout).
)");
}

// A decimal number as C writes it: [+-] digits [. digits] [e [+-] digits]. No nan, inf or hex.
bool decimal_syntax(const std::string& s) {
  std::size_t k = 0;
  if (k < s.size() && (s[k] == '+' || s[k] == '-')) ++k;
  std::size_t digits = 0;
  while (k < s.size() && std::isdigit(static_cast<unsigned char>(s[k]))) ++k, ++digits;
  if (k < s.size() && s[k] == '.') {
    ++k;
    while (k < s.size() && std::isdigit(static_cast<unsigned char>(s[k]))) ++k, ++digits;
  }
  if (digits == 0) return false;
  if (k < s.size() && (s[k] == 'e' || s[k] == 'E')) {
    ++k;
    if (k < s.size() && (s[k] == '+' || s[k] == '-')) ++k;
    std::size_t exponent = 0;
    while (k < s.size() && std::isdigit(static_cast<unsigned char>(s[k]))) ++k, ++exponent;
    if (exponent == 0) return false;
  }
  return k == s.size();
}

struct Input {
  long long n = 0;
  double radius = 0, lx = 0, ly = 0;
  std::vector<double> values;  // x y u v per particle
};

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(std::size_t line, const std::string& what) const {
    throw BadInput(text(billiard_cli::printable(file_, 200), ":", line, ": ", what));
  }

  // The fields of line `line` (1-based), which must hold `count` of them.
  std::vector<std::string> fields(const std::string& content, std::size_t line, std::size_t count,
                                  const std::string& what) const {
    std::istringstream in(content);
    std::vector<std::string> out;
    for (std::string word; in >> word;) out.push_back(word);
    if (out.size() != count) {
      fail(line, text("expected ", count == 1 ? "1 number" : text(count, " numbers"), " (", what, "), got ",
                      out.size(), out.empty() ? " (an empty line)" : "", "; write exactly ", what, " on this line"));
    }
    return out;
  }

  double number(const std::string& word, std::size_t line, const std::string& name) const {
    if (!decimal_syntax(word)) {
      fail(line, text(name, " must be a decimal number, got ", in_quotes(word), " (nan and inf are not accepted)"));
    }
    const double value = std::strtod(word.c_str(), nullptr);
    if (!billiard::limits::bounded(value)) fail(line, text(name, " ", billiard::limits::kMustBeBounded, ", got ", in_quotes(word)));
    return value;
  }

  Input read() const {
    std::ifstream in(file_, std::ios::binary);
    if (!in) throw BadInput(text("cannot read ", in_quotes(file_), " (no such file, or not readable)"));
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      lines.push_back(line);
    }
    if (in.bad()) throw BadInput(text("cannot read ", in_quotes(file_)));
    // Blank lines at the end are accepted; elsewhere they are an error.
    auto blank = [](const std::string& s) { return s.find_first_not_of(" \t\f\v") == std::string::npos; };
    while (!lines.empty() && blank(lines.back())) lines.pop_back();
    if (lines.empty()) fail(1, "the file is empty; line 1 must hold N, line 2 the radius, line 3 Lx Ly, then x y u v per particle");

    Input input;
    const std::string word = fields(lines[0], 1, 1, "N, the number of particles")[0];
    bool whole = !word.empty();
    for (std::size_t k = word[0] == '+' ? 1 : 0; k < word.size(); ++k) whole = whole && std::isdigit(static_cast<unsigned char>(word[k]));
    if (word[0] == '-' && word.size() > 1) fail(1, text("N must not be negative, got ", in_quotes(word)));
    if (!whole || word == "+") fail(1, text("N must be a whole number such as 10, got ", in_quotes(word)));
    const std::string digits = word.substr(word[0] == '+' ? 1 : 0);
    if (digits.size() > 7 || std::stoll(digits) > kMaxParticles) {
      fail(1, text("N = ", billiard_cli::printable(word, 30), " is too large: at most ", thousands(kMaxParticles), " particles"));
    }
    input.n = std::stoll(digits);

    if (lines.size() < 2) fail(2, "the file ends after line 1; line 2 must hold the radius");
    input.radius = number(fields(lines[1], 2, 1, "the radius")[0], 2, "the radius");
    if (!(input.radius > 0)) fail(2, text("the radius must be positive, got ", input.radius));

    if (lines.size() < 3) fail(3, "the file ends after line 2; line 3 must hold the box lengths Lx Ly");
    const auto box = fields(lines[2], 3, 2, "the box lengths Lx Ly");
    input.lx = number(box[0], 3, "Lx");
    input.ly = number(box[1], 3, "Ly");
    if (!(input.lx > 0)) fail(3, text("the box length Lx must be positive, got ", input.lx));
    if (!(input.ly > 0)) fail(3, text("the box length Ly must be positive, got ", input.ly));
    const double extent = std::max(input.lx, input.ly);
    if (input.radius < kRelativeRadius * extent) {
      fail(2, text("the radius ", input.radius, " is too small for a box of ", extent,
                   ": it must be at least 1e-6 max(Lx, Ly) (positions are computed to about 1e-16 of the box)"));
    }
    const double diameter = 2 * input.radius;
    if (diameter > input.lx || diameter > input.ly) {
      fail(2, text("the radius ", input.radius, " is too large for the box ", input.lx, " x ",
                   input.ly, ": a particle needs 2 R <= Lx and 2 R <= Ly"));
    }

    const auto n = static_cast<std::size_t>(input.n);
    input.values.resize(4 * n);
    const double r = input.radius;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t line = 4 + i;
      if (lines.size() < line) {
        fail(line, text("the file ends after ", i, " particle line(s), but line 1 says N = ", n,
                        "; add the missing particles (x y u v) or correct N"));
      }
      const auto words = fields(lines[3 + i], line, 4, text("x y u v of particle ", i));
      const char* names[4] = {"x", "y", "u", "v"};
      for (int k = 0; k < 4; ++k) input.values[4 * i + k] = number(words[k], line, text(names[k], " of particle ", i));
      const double x = input.values[4 * i], y = input.values[4 * i + 1];
      if (x < 0 || x > input.lx || y < 0 || y > input.ly) {
        fail(line, text("particle ", i, " at (", x, ", ", y, ") is outside the box [0, ",
                        input.lx, "] x [0, ", input.ly, "]"));
      }
      if (x < r || input.lx - x < r || y < r || input.ly - y < r) {
        fail(line, text("particle ", i, " at (", x, ", ", y,
                        ") overlaps a wall: its centre must be at least the radius ", r, " from every wall"));
      }
    }
    if (lines.size() > 3 + n) {
      fail(3 + n + 1, text("one line too many: line 1 says N = ", n, " particles, and they end on line ", 3 + n,
                           "; remove the extra line(s) or correct N"));
    }
    check_overlaps(input);
    return input;
  }

 private:
  // Two particles overlap when their centres are less than 2R apart: a hash grid of cells 2R
  // wide, so that only neighbouring cells are compared.
  void check_overlaps(const Input& input) const {
    const double cell = 2 * input.radius;
    const double contact = cell * cell;
    std::unordered_map<std::int64_t, std::vector<std::size_t>> cells;
    auto key = [](std::int64_t cx, std::int64_t cy) { return cx * 4000003 + cy; };
    const auto n = static_cast<std::size_t>(input.n);
    for (std::size_t i = 0; i < n; ++i) {
      const double x = input.values[4 * i], y = input.values[4 * i + 1];
      // (cells across: at most max(L) / 2R <= 5e5, see the radius limit)
      const auto cx = static_cast<std::int64_t>(x / cell), cy = static_cast<std::int64_t>(y / cell);
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
          const auto found = cells.find(key(cx + dx, cy + dy));
          if (found == cells.end()) continue;
          for (std::size_t j : found->second) {
            const double ex = x - input.values[4 * j], ey = y - input.values[4 * j + 1];
            const double squared = ex * ex + ey * ey;
            if (squared < contact) {
              fail(4 + i, text("particle ", i, " overlaps particle ", j, " (line ", 4 + j, "): centres ",
                               std::sqrt(squared), " apart, less than 2 R = ", cell,
                               "; move one of them"));
            }
          }
        }
      }
      cells[key(cx, cy)].push_back(i);
    }
  }

  std::string file_;
};

struct Options {
  bool help = false;
  bool physical = false;
  std::string file;
  double end_time = 0;
};

constexpr const char* kUsage = "usage: particles [--physical] FILE END_TIME; particles --help";

Options parse(int argc, char** argv) {
  Options options;
  std::vector<std::string> positional;
  for (int k = 1; k < argc; ++k) {
    const std::string argument = argv[k];
    if (argument == "--help" || argument == "-h") {
      options.help = true;
    } else if (argument == "--physical") {
      options.physical = true;
    } else if (argument.size() > 1 && argument[0] == '-' && !std::isdigit(static_cast<unsigned char>(argument[1])) &&
               argument[1] != '.') {
      throw BadInput(text("unknown option ", in_quotes(argument), " (", kUsage, ")"));
    } else {
      positional.push_back(argument);
    }
  }
  if (options.help) return options;
  if (positional.size() != 2) {
    throw BadInput(text("expected FILE END_TIME, got ", positional.size(), " argument(s) (", kUsage, ")"));
  }
  options.file = positional[0];
  const std::string& end = positional[1];
  const double value = decimal_syntax(end) ? std::strtod(end.c_str(), nullptr) : std::nan("");
  if (!(value >= 0 && billiard::limits::bounded(value))) {
    throw BadInput(text("END_TIME must be a number from 0 to 1e50, got ", in_quotes(end), " (", kUsage, ")"));
  }
  options.end_time = value;
  return options;
}

// Runs the engine to END_TIME and returns the whole output. The event log, read in chunks,
// gives each particle's counts.
std::string run(const Input& input, const Options& options) {
  const auto n = static_cast<std::size_t>(input.n);
  billiard::Settings settings;
  settings.exchange_velocities = !options.physical;
  billiard::Simulation sim(billiard::box({0, 0}, {input.lx, input.ly}), settings);
  if (n > 0) {
    billiard::Coordinates positions(static_cast<Eigen::Index>(n), 2), velocities(static_cast<Eigen::Index>(n), 2);
    for (std::size_t i = 0; i < n; ++i) {
      const auto row = static_cast<Eigen::Index>(i);
      positions.row(row) << input.values[4 * i], input.values[4 * i + 1];
      velocities.row(row) << input.values[4 * i + 2], input.values[4 * i + 3];
    }
    try {
      sim.add_discs(positions, velocities, input.radius);
    } catch (const std::invalid_argument& error) {  // (the checks above should have caught it)
      throw BadInput(text(billiard_cli::printable(options.file, 200), ": ", billiard_cli::printable(error.what())));
    }
  }
  std::vector<int> walls(n, 0), others(n, 0);
  sim.set_log_events(true);
  std::int64_t total = 0;
  for (;;) {
    const billiard::AdvanceResult result = sim.advance(kEventsPerChunk, options.end_time - sim.time());
    for (const billiard::EventRecord& event : sim.event_log()) {
      if (event.kind == billiard::EventKind::DiscWall) {
        ++walls[static_cast<std::size_t>(event.disc)];
      } else if (event.kind == billiard::EventKind::DiscDisc) {
        ++others[static_cast<std::size_t>(event.disc)];
        ++others[static_cast<std::size_t>(event.other)];
      }
    }
    sim.clear_event_log();
    total += result.collisions;
    if (result.stuck) throw std::runtime_error(result.stuck_reason);
    if (total > kMaxCollisions) {
      throw BadInput(text("END_TIME ", options.end_time, " is too far: more than ", thousands(kMaxCollisions),
                          " collisions before time ", sim.time(), "; choose a smaller END_TIME"));
    }
    if (result.collisions < kEventsPerChunk) break;
  }
  const billiard::State state = sim.current_state();
  std::string out;
  char line[200];
  for (std::size_t i = 0; i < n; ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    const int length = std::snprintf(line, sizeof line, "%.6f, %.6f, %d, %d\n", state.positions(row, 0), state.positions(row, 1),
                                     walls[i], others[i]);
    out.append(line, static_cast<std::size_t>(length));
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options options = parse(argc, argv);
    if (options.help) {
      std::cout << help();
      return 0;
    }
    const Input input = Reader(options.file).read();
    std::cout << run(input, options) << std::flush;
    return 0;
  } catch (const BadInput& error) {
    std::cerr << "particles: " << error.what() << "\n";
    return 2;
  } catch (const std::exception& error) {
    std::cerr << "particles: unexpected error: " << billiard_cli::printable(error.what()) << "\n";
    return 1;
  }
}
