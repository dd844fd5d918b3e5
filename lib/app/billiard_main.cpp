// The `billiard` command: runs the six course functions on one table and reports.
//
//   billiard [TABLE_RADIUS CIRCLE_RADIUS N] [--seed S] [--collisions K]
//            [--drift-collisions M] [--output DIR] [--gravity GX,GY | --walls FILE | --cells SIZE]
//
// It places N circles (task 1), gives them velocities (task 2), draws the table (task 3),
// records a movie of K collisions (tasks 4 and 5), runs M more collisions and reports how
// well the mean squared velocity was conserved, before and after the correction (task 6).
// With a stage's option it runs that extension stage (7 gravity, 8 walls, 9 sectors) after
// tasks 1-3 instead: a movie of K events drawn by the command, then M more events and what the
// stage conserves (or, for sectors, how many pair tests each collision took).
// Built from a student's tasks/, it runs what it can, reports the tasks in order, and says which
// are missing and which wait for them.
//
// Exit status: 0 all done; 1 some task is not implemented yet or failed; 2 bad input (one
// line on stderr, nothing written).
#include "billiard/argument_checks.hpp"
#include "billiard/course.hpp"
#include "billiard/not_implemented.hpp"
#include "cli_text.hpp"
#include "stages.hpp"

#include <atomic>
#include <algorithm>
#include <cerrno>
#include <cctype>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;

namespace {

using namespace billiard_cli;
using billiard_cli::Stage;

// Limits, so that every accepted run ends within minutes and no number of the run overflows.
// Velocities are of order 1, so lengths, times and their squares stay near the radii's scale.
constexpr double kMinRadius = 0.001, kMaxRadius = 1000;  // only the ratio of the radii matters
constexpr long long kMaxCircles = 1000;
constexpr long long kMaxCollisions = 1'000'000;
constexpr long long kMaxDriftCollisions = 100'000'000;
constexpr long long kMaxMovieSize = 2'000'000;          // N x K: circles times key frames
constexpr long long kMaxPairChecks = 10'000'000'000LL;  // (K + M) x N(N-1)/2: every pair, every collision
// Sectors test only neighbours: about kSectorPairsPerCircle pairs per circle and event (with
// cells near 2 CIRCLE_RADIUS), so (K + M) x N x that within the same bound.
constexpr long long kSectorPairsPerCircle = 10;

// The files the command writes, in this order.
constexpr const char* kFiles[] = {"table.svg", "movie.svg"};

constexpr const char* kUsage = "usage: billiard [TABLE_RADIUS CIRCLE_RADIUS N] [options]; see billiard --help";

std::string help() {
  return text(R"(billiard: N hard circles colliding elastically on a circular table.

usage: billiard [TABLE_RADIUS CIRCLE_RADIUS N] [options]
       billiard 10 1 10              (the default: 10 circles of radius 1, table radius 10)

Runs the six course functions: places the circles (task 1), gives them random velocities
(task 2), draws the table (task 3), records a movie of the first collisions (tasks 4 and 5),
runs more collisions and reports the drift of the mean squared velocity <v^2> with and
without the correction (task 6).

options:
  --seed S               random seed, a whole number (default 1); the same seed gives the
                         same table
  --collisions K         collisions in the movie (default 100)
  --drift-collisions M   further collisions to measure the energy drift (default 10000)
  --output DIR           folder for table.svg and movie.svg (default billiard-output; created
                         if missing); open them in a web browser
  -h, --help             this help

extension stages (one at a time; each runs tasks 1-3, then the stage instead of tasks 4-6):
  --gravity GX,GY        task 7: uniform gravity (GX, GY), e.g. --gravity 0,-1; the movie
                         shows the parabolas; reports the drift of the mean energy
  --walls FILE           task 8: straight walls inside the table, one per line of FILE:
                         AX AY BX BY (its end points; # starts a comment); circles placed on a
                         wall are moved off it
  --cells SIZE           task 9: sectors, square cells of side SIZE >= 2 CIRCLE_RADIUS; reports
                         the pair tests per collision against all pairs' N(N-1)/2

limits, so that every run ends within minutes and no number overflows:
)",
              "  TABLE_RADIUS and CIRCLE_RADIUS from ", kMinRadius, " to ", kMaxRadius, " (only their ratio matters)\n",
              "  N <= ", thousands(kMaxCircles), ", K <= ", thousands(kMaxCollisions),
              ", M <= ", thousands(kMaxDriftCollisions), "\n",
              "  N x K <= ", thousands(kMaxMovieSize), " (the size of the movie; ", billiard_cli::StageMovie::kSamplesPerParabola,
              " N x K under gravity)\n",
              "  (K + M) x N(N-1)/2 <= ", thousands(kMaxPairChecks), " (every collision checks all pairs of circles;\n",
              "  with --walls also N x walls; with --cells (K + M) x N x ", kSectorPairsPerCircle, " instead)\n",
              "  |GX|, |GY| <= ", billiard_cli::kMaxGravity, ", at most ", billiard_cli::kMaxWalls, " walls, at most ",
              billiard::checks::kMaxCellsAcross, " cells across the table\n",
              R"(exit status: 0 done; 1 a task is not implemented yet or failed; 2 bad input (one line on
stderr, nothing written).
)");
}

// A radius: a plain decimal number (read_number) in range.
double parse_radius(std::string_view value, std::string_view name, std::string_view example) {
  double number = 0;
  if (!read_number(value, number) || !(number >= kMinRadius && number <= kMaxRadius)) {
    throw BadInput(text(name, " must be a number from ", kMinRadius, " to ", kMaxRadius, ", got ", in_quotes(value),
                        " (only the ratio of the radii matters: scale both, for example ", example, "; ", kUsage,
                        ")"));
  }
  return number;
}

long long parse_whole(std::string_view value, std::string_view name, long long low, long long high,
                      std::string_view why) {
  long long number = 0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), number);
  if (error != std::errc() || end != value.data() + value.size() || number < low || number > high) {
    throw BadInput(text(name, " must be a whole number from ", low, " to ", thousands(high), why, ", got ",
                        in_quotes(value), " (", kUsage, ")"));
  }
  return number;
}

// A negative number (or -inf, -nan) is a number given, to be refused as one, not an option.
bool looks_like_number(std::string_view argument) {
  double ignored = 0;
  const auto [end, error] = std::from_chars(argument.data(), argument.data() + argument.size(), ignored);
  const bool whole = end == argument.data() + argument.size() && error != std::errc::invalid_argument;
  return argument.size() > 1 && argument[0] == '-' &&
         (std::isdigit(static_cast<unsigned char>(argument[1])) || argument[1] == '.' || whole);
}

struct Options {
  double table_radius = 10, circle_radius = 1;
  int n = 10;
  std::uint64_t seed = 1;
  int collisions = 100;
  long long drift_collisions = 10000;
  fs::path output = "billiard-output";
  bool help = false;
  StageOptions stage;
  std::string_view stage_option;  // the option that chose the stage
};

// The stage an option chooses; only one at a time.
void choose_stage(Options& options, Stage stage, std::string_view option) {
  if (options.stage.stage != Stage::None && options.stage.stage != stage) {
    throw BadInput(text(options.stage_option, " and ", option, " choose two extension stages; give one of them (",
                        kUsage, ")"));
  }
  if (!stage_built(stage)) {
    throw BadInput(text(option, ": the ", stage_name(stage), " stage (task ", task_number(stage),
                        ") is switched off in this course (tests/grader/course.txt)"));
  }
  options.stage.stage = stage;
  options.stage_option = option;
}

Options parse(int argc, char** argv) {
  Options options;
  std::vector<std::string_view> numbers;
  for (int k = 1; k < argc; ++k) {
    std::string_view argument = argv[k];
    if (argument == "-h" || argument == "--help") {
      options.help = true;
      return options;
    }
    if (argument.substr(0, 2) != "--" && (argument.empty() || argument[0] != '-' || looks_like_number(argument))) {
      numbers.push_back(argument);
      continue;
    }
    // --name VALUE or --name=VALUE
    std::string_view name = argument, value;
    if (const auto equals = argument.find('='); equals != std::string_view::npos) {
      name = argument.substr(0, equals);
      value = argument.substr(equals + 1);
    } else if (name == "--seed" || name == "--collisions" || name == "--drift-collisions" || name == "--output" ||
               name == "--gravity" || name == "--walls" || name == "--cells") {
      if (k + 1 >= argc) throw BadInput(text(name, " needs a value (", kUsage, ")"));
      value = argv[++k];
    }
    if (name == "--seed") {
      options.seed = static_cast<std::uint64_t>(parse_whole(value, "--seed", 0, 9'000'000'000'000'000'000LL, ""));
    } else if (name == "--collisions") {
      options.collisions = static_cast<int>(parse_whole(value, "--collisions", 0, kMaxCollisions, ""));
    } else if (name == "--drift-collisions") {
      options.drift_collisions = parse_whole(value, "--drift-collisions", 0, kMaxDriftCollisions, "");
    } else if (name == "--output") {
      if (value.empty()) throw BadInput(text("--output needs a folder name (", kUsage, ")"));
      options.output = fs::path(value);
    } else if (name == "--gravity") {
      choose_stage(options, Stage::Gravity, "--gravity");
      options.stage.gravity = parse_gravity(value);
    } else if (name == "--walls") {
      choose_stage(options, Stage::Walls, "--walls");
      if (value.empty()) throw BadInput(text("--walls needs a file name (", kUsage, ")"));
      options.stage.walls_file = fs::path(value);
    } else if (name == "--cells") {
      choose_stage(options, Stage::Sectors, "--cells");
      double size = 0;
      if (!read_number(value, size) || size <= 0) {
        throw BadInput(text("--cells must be a positive number, the side of a cell (at least 2 CIRCLE_RADIUS), got ",
                            in_quotes(value), " (", kUsage, ")"));
      }
      options.stage.cell_size = size;
    } else {
      throw BadInput(text("unknown option ", in_quotes(argument), " (", kUsage, ")"));
    }
  }
  if (!numbers.empty() && numbers.size() != 3) {
    throw BadInput(text("expected three numbers TABLE_RADIUS CIRCLE_RADIUS N (or none for 10 1 10), got ",
                        numbers.size(), " (", kUsage, ")"));
  }
  if (numbers.size() == 3) {
    options.table_radius = parse_radius(numbers[0], "TABLE_RADIUS", "10 1 10 or 1 0.1 10");
    options.circle_radius = parse_radius(numbers[1], "CIRCLE_RADIUS", "10 1 10 or 1 0.1 10");
    options.n = static_cast<int>(parse_whole(numbers[2], "N", 0, kMaxCircles, " (every collision checks all pairs)"));
    if (options.circle_radius >= options.table_radius) {
      throw BadInput(text("CIRCLE_RADIUS ", in_quotes(numbers[1]), " must be smaller than TABLE_RADIUS ",
                          in_quotes(numbers[0]), " for a circle to fit on the table (", kUsage, ")"));
    }
  }
  const Stage stage = options.stage.stage;
  if (stage == Stage::Sectors) {
    const double size = options.stage.cell_size;
    if (size < 2 * options.circle_radius) {
      throw BadInput(text("--cells ", size, " must be at least 2 CIRCLE_RADIUS = ", 2 * options.circle_radius,
                          ", so that circles touch only circles in neighbouring cells"));
    }
    if (2 * options.table_radius / size > billiard::checks::kMaxCellsAcross) {
      throw BadInput(text("--cells ", size, " makes ", 2 * options.table_radius / size, " cells across the table (at most ",
                          billiard::checks::kMaxCellsAcross, "); use --cells ",
                          2 * options.table_radius / billiard::checks::kMaxCellsAcross, " or more"));
    }
  }
  if (stage == Stage::Walls) options.stage.walls = read_walls(options.stage.walls_file, options.table_radius);
  const long long n = options.n, collisions = options.collisions;
  const long long frames = stage == Stage::Gravity ? billiard_cli::StageMovie::kSamplesPerParabola : 1;
  if (n * collisions * frames > kMaxMovieSize) {
    throw BadInput(text("--collisions ", collisions, " with N = ", n, " makes too large a movie; use --collisions ",
                        kMaxMovieSize / std::max(n * frames, 1LL), " or fewer (N x K <= ", thousands(kMaxMovieSize),
                        frames > 1 ? text(", ", frames, " frames per collision under gravity") : std::string(), ")"));
  }
  const long long walls = static_cast<long long>(options.stage.walls.size());
  const long long pairs = stage == Stage::Sectors ? n * kSectorPairsPerCircle : n * (n - 1) / 2 + n * walls;
  const long long events = collisions + options.drift_collisions;
  if (pairs > 0 && events > kMaxPairChecks / pairs) {
    const long long most = kMaxPairChecks / pairs;
    throw BadInput(text("--collisions ", collisions, " and --drift-collisions ", options.drift_collisions,
                        " with N = ", n, " make too long a run; use ",
                        collisions <= most ? text("--drift-collisions ", most - collisions)
                                           : text("--collisions and --drift-collisions adding up to ", most),
                        " or fewer (", stage == Stage::Sectors ? text("(K + M) x N x ", kSectorPairsPerCircle) : std::string("(K + M) x N(N-1)/2"),
                        " <= ", thousands(kMaxPairChecks), ": every collision checks ",
                        stage == Stage::Sectors ? "the neighbours of every circle" : "all pairs", ")"));
  }
  return options;
}

// Removes the files and folders of an unfinished run when the run is interrupted: the paths
// of the output folder's Staging, children before parents, or null.
std::atomic<const std::vector<std::string>*> g_partial_output{nullptr};

extern "C" void remove_partial_output(int signal_number) {
  // Only async-signal-safe calls: unlink and rmdir (each path is a file or an empty folder).
  if (const auto* paths = g_partial_output.load()) {
    for (const auto& path : *paths) {
      ::unlink(path.c_str());
      ::rmdir(path.c_str());
    }
  }
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);
}

// The output folder. Before anything runs, the constructor creates it (and any missing
// parents) and a private folder inside it: a folder that cannot be created or written to is
// bad input, found before anything is printed or written. The files are written into the
// private folder and moved into place at the end. A run that is refused, fails before
// writing a file, or is interrupted removes every folder the constructor created, so it
// leaves no partial output.
class Staging {
 public:
  explicit Staging(const fs::path& output) : output_(output) {
    const std::string given = output.string();
    const auto refuse = [&](const std::string& problem) {
      remove_created();
      throw BadInput(text("--output ", in_quotes(given), problem));
    };
    fs::path prefix;
    for (const auto& part : output) {
      prefix /= part;
      std::error_code error;
      if (fs::create_directory(prefix, error)) {
        created_.push_back(prefix);
      } else if (error) {
        // The part of the path that is in the way: "--output 'a/b': 'a' is a file", or the whole.
        const std::string part_named = prefix == output ? "" : ": " + in_quotes(prefix.string());
        std::error_code ignored;
        if (fs::exists(prefix, ignored) && !fs::is_directory(prefix, ignored)) {
          refuse(part_named + " is a file, not a folder; give the name of a folder (it is created if missing)");
        }
        if (fs::is_symlink(prefix, ignored) && !fs::exists(prefix, ignored)) {
          refuse(text(part_named, " is a link to ", in_quotes(fs::read_symlink(prefix, ignored).string()),
                      ", which does not exist; give a folder you can write to"));
        }
        refuse(text(": cannot create ", prefix == output ? "this folder" : "the folder " + in_quotes(prefix.string()),
                    " (", error.message(), "); give a folder you can write to"));
      }
    }
    for (const char* name : kFiles) {
      std::error_code ignored;
      if (fs::is_directory(output / name, ignored)) {
        refuse(text(" has a folder named ", name, " where the picture goes; remove it or give another folder"));
      }
    }
    std::string private_folder = (output / ".billiard-partial-XXXXXX").string();
    if (::mkdtemp(private_folder.data()) == nullptr) {
      const int error = errno;
      refuse(text(": cannot write in this folder (", std::generic_category().message(error),
                  "); give a folder you can write to"));
    }
    path_ = private_folder;
    // What an interruption removes: the files, then the private folder, then the created folders.
    for (const char* name : kFiles) cleanup_.push_back(file(name).string());
    cleanup_.push_back(path_.string());
    for (auto folder = created_.rbegin(); folder != created_.rend(); ++folder) cleanup_.push_back(folder->string());
    g_partial_output = &cleanup_;
    for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
      struct sigaction now {};
      // A signal the caller ignores (nohup, a background job) stays ignored.
      if (::sigaction(signal_number, nullptr, &now) == 0 && now.sa_handler != SIG_IGN) {
        std::signal(signal_number, remove_partial_output);
      }
    }
  }
  Staging(const Staging&) = delete;
  Staging& operator=(const Staging&) = delete;
  ~Staging() {
    g_partial_output = nullptr;
    std::error_code ignored;
    fs::remove_all(path_, ignored);
    remove_created();
  }
  fs::path file(const std::string& name) const { return path_ / name; }
  // Moves the files written so far into the output folder; returns their final paths.
  std::vector<fs::path> publish() {
    std::vector<fs::path> published;
    for (const char* name : kFiles) {
      if (!fs::exists(file(name))) continue;
      const fs::path target = output_ / name;
      fs::rename(file(name), target);
      published.push_back(target);
    }
    return published;
  }

 private:
  // Removes the folders the constructor created, deepest first, where they are still empty.
  void remove_created() {
    for (auto folder = created_.rbegin(); folder != created_.rend(); ++folder) {
      std::error_code ignored;
      fs::remove(*folder, ignored);
    }
  }

  fs::path output_, path_;
  std::vector<fs::path> created_;     // folders the constructor created, parents first
  std::vector<std::string> cleanup_;  // for remove_partial_output
};

// What each task did, printed in task order at the end (the movie, task 5, runs before the
// further collisions of task 4). A task that cannot run because an earlier one is missing
// says which one it waits for.
class Report {
 public:
  void done(int task, const std::string& text) { lines_[index(task)].push_back(text); }
  void failed(int task, const std::exception& error) {
    lines_[index(task)].push_back("!! " + printable(error.what()));
    if (first_failed_ == 0 || task < first_failed_) first_failed_ = task;
  }
  void waits(int task, int for_task) {
    if (lines_[index(task)].empty()) lines_[index(task)].push_back(waiting_for(for_task));
  }
  static std::string waiting_for(int task) {
    return "waits for task " + std::to_string(task) + " (" + kNames[index(task)] + ")";
  }
  // Prints the tasks, moves the files into place and says what was written; the exit status.
  int finish(Staging& staging) const {
    for (int task = 1; task <= kTasks; ++task) {
      std::string label = "  task " + std::to_string(task) + " " + kNames[index(task)];
      label.resize(kLabelWidth, ' ');
      for (const auto& line : lines_[index(task)]) {
        std::cout << label << line << "\n";
        label.assign(kLabelWidth, ' ');  // further lines of the same task: indented only
      }
    }
    for (const auto& file : staging.publish()) std::cout << "  wrote " << printable(file.string()) << "\n";
    if (first_failed_ == 0) return 0;
    std::cout << "billiard: the tasks marked !! need work; start with task " << first_failed_ << " ("
              << kNames[index(first_failed_)] << ")\n";
    return 1;
  }

 private:
  static constexpr int kTasks = 9;  // the six tasks and the three extension stages
  static constexpr const char* kNames[kTasks] = {"init_billiard", "init_velocities", "visualize_table",
                                                 "propagate",     "movie",           "kinetic_energy",
                                                 "gravity",       "walls",           "sectors"};
  static std::size_t index(int task) { return static_cast<std::size_t>(task - 1); }
  static constexpr std::size_t kLabelWidth = 27;  // "  task 2 init_velocities" and a gap
  std::vector<std::string> lines_[kTasks];
  int first_failed_ = 0;  // 0: none
};

// The task an error comes from: its own number for a stub's NotImplemented, else `task`.
int task_of(const std::exception& error, int task) {
  const auto* missing = dynamic_cast<const billiard::NotImplemented*>(&error);
  return missing != nullptr ? missing->task_number() : task;
}

// An extension stage after tasks 1-3: a movie of K events drawn by the command, M more events,
// and what the stage conserves (gravity: the mean energy, task 7's mean_energy; walls: <v^2>,
// task 6's kinetic_energy) or, for sectors, the pair tests per collision (pair_time's count).
void run_stage(const Options& options, billiard::Coordinates& coordinates, billiard::Velocities& velocities,
               Report& report, Staging& staging) {
  using namespace billiard;
  const StageOptions& stage = options.stage;
  const int task = task_number(stage.stage), n = options.n;
  const double table_radius = options.table_radius, circle_radius = options.circle_radius;
  const Vector g = stage.stage == Stage::Gravity ? stage.gravity : Vector::Zero();
  const bool moving = n > 0 && (velocities.squaredNorm() > 0 || g.squaredNorm() > 0);
  if (!moving) {
    report.done(task, "nothing moves, so nothing collides");
    return;
  }
  // What the run conserves, before it.
  const auto conserved = [&]() {
#ifdef BILLIARD_WITH_GRAVITY
    if (stage.stage == Stage::Gravity) return mean_energy(n, coordinates, velocities, g);
#endif
    return kinetic_energy(n, velocities);
  };
  const int conserved_task = stage.stage == Stage::Gravity ? 7 : 6;
  const char* conserved_name = stage.stage == Stage::Gravity ? "mean energy" : "<v^2>";
  std::optional<double> before;
  try {
    before = conserved();
  } catch (const std::exception& error) {
    report.failed(task_of(error, conserved_task), error);
  }
  try {
    StageMovie recording(table_radius, circle_radius, coordinates);
    double elapsed = 0;
    for (int k = 0; k < options.collisions; ++k) {
      const Coordinates start = coordinates;
      const Velocities start_velocities = velocities;
      const Collision event = stage_step(stage, table_radius, circle_radius, n, coordinates, velocities);
      recording.flight(start, start_velocities, g, event.time, coordinates);
      elapsed += event.time;
    }
    recording.write(staging.file("movie.svg"), stage.walls);
    report.done(task, text("recorded ", options.collisions, " collisions", stage.stage == Stage::Gravity ? " (parabolas sampled between them)" : "",
                           ": movie.svg"));
    const long long pair_tests_before = pair_time_calls();
    for (long long k = 0; k < options.drift_collisions; ++k) {
      elapsed += stage_step(stage, table_radius, circle_radius, n, coordinates, velocities).time;
    }
    report.done(task, text(options.drift_collisions, " more collisions, simulated time ", rounded(elapsed, 6)));
    if (stage.stage == Stage::Sectors && options.drift_collisions > 0) {
      const double per_collision = double(pair_time_calls() - pair_tests_before) / double(options.drift_collisions);
      const double all_pairs = 0.5 * n * (n - 1);
      report.done(task, text("pair tests per collision: ", rounded(per_collision, 4), " (all pairs: ", thousands(std::llround(all_pairs)),
                             per_collision > 0 ? text(", ", thousands(std::llround(all_pairs / per_collision)), "x fewer)")
                                               : std::string("; none counted: test pairs with pair_time)")));
    }
  } catch (const std::exception& error) {
    report.failed(task_of(error, task), error);
    return;
  }
  if (before) {
    try {
      const double after = conserved();
      const double scale = std::abs(*before) > 0 ? std::abs(*before) : 1.0;
      report.done(conserved_task, text(conserved_name, " before ", rounded(*before, 12), ", after ", rounded(after, 12),
                                       ", relative drift ", rounded(std::abs(after - *before) / scale, 3)));
    } catch (const std::exception& error) {
      report.failed(task_of(error, conserved_task), error);
    }
  }
}

int run(const Options& options, Staging& staging) {
  using namespace billiard;
  const double table_radius = options.table_radius, circle_radius = options.circle_radius;
  const int n = options.n;
  Rng rng(options.seed);
  Report report;

  // Task 1 first: an invalid_argument here means the circles cannot fit, which is bad input,
  // reported before anything is printed or written (the staging removes the folders it made).
  std::optional<Coordinates> coordinates;
  try {
    coordinates = init_billiard(table_radius, circle_radius, n, rng);
    report.done(1, "placed the circles");
  } catch (const NotImplemented& missing) {
    report.failed(1, missing);
  } catch (const std::invalid_argument& error) {
    throw BadInput(printable(error.what()));
  }

  // Circles on a wall are moved off it before anything is printed: when they cannot all fit
  // between the walls, that is bad input.
  const Stage stage = options.stage.stage;
  if (stage == Stage::Walls && coordinates) {
    const int moved = place_clear_of_walls(table_radius, circle_radius, *coordinates, options.stage.walls, rng);
    if (moved > 0) report.done(1, text("(the command moved ", moved, moved == 1 ? " circle" : " circles", " off the walls)"));
  }

  std::cout << "billiard: " << n << (n == 1 ? " circle" : " circles") << " of radius " << circle_radius
            << " on a table of radius " << table_radius << " (area fraction "
            << rounded(n * circle_radius * circle_radius / (table_radius * table_radius), 3) << "), seed "
            << options.seed << "\n";
  if (!coordinates) {
    for (int task : stage == Stage::None ? std::vector<int>{2, 3, 4, 5, 6} : std::vector<int>{2, 3, task_number(stage)}) {
      report.waits(task, 1);
    }
    return report.finish(staging);
  }

  std::optional<Velocities> velocities;
  try {
    velocities = init_velocities(n, *coordinates, rng);
    report.done(2, "gave each circle a random velocity");
  } catch (const std::exception& error) {
    report.failed(2, error);
  }
  try {
    visualize_table(table_radius, circle_radius, n, *coordinates, staging.file("table.svg"));
    report.done(3, "drew the table: table.svg");
  } catch (const std::exception& error) {
    report.failed(3, error);
  }
  if (!velocities) {
    for (int task : stage == Stage::None ? std::vector<int>{4, 5, 6} : std::vector<int>{task_number(stage)}) {
      report.waits(task, 2);
    }
    return report.finish(staging);
  }
  if (stage != Stage::None) {
    run_stage(options, *coordinates, *velocities, report, staging);
    return report.finish(staging);
  }

  std::optional<double> before;
  try {
    before = kinetic_energy(n, *velocities);
  } catch (const std::exception& error) {
    report.failed(6, error);
  }
  // With no circles, or all at rest, nothing ever collides: the movie is a still picture.
  const bool moving = n > 0 && velocities->squaredNorm() > 0;
  bool advanced = moving;  // propagate works (as far as the movie could tell)
  try {
    movie(table_radius, circle_radius, n, *coordinates, *velocities, moving ? options.collisions : 0,
          staging.file("movie.svg"));
    report.done(5, "recorded " + std::to_string(moving ? options.collisions : 0) + " collisions: movie.svg");
  } catch (const std::exception& error) {
    // The movie runs propagate: a missing or failing propagate is task 4's problem.
    const int task = task_of(error, 5);
    report.failed(task, error);
    if (task == 4) report.waits(5, 4);
    advanced = advanced && task == 5;  // only movie is missing: propagate may work
  }
  if (!moving) report.done(4, "nothing moves, so nothing collides");
  try {
    double elapsed = 0;
    for (long long k = 0; advanced && k < options.drift_collisions; ++k) {
      elapsed += propagate(table_radius, circle_radius, n, *coordinates, *velocities).time;
    }
    if (advanced) {
      report.done(4, std::to_string(options.drift_collisions) + " more collisions, simulated time " + rounded(elapsed, 6));
    }
  } catch (const std::exception& error) {
    report.failed(4, error);
    advanced = false;
  }
  if (before && !(advanced && *before > 0)) {
    report.done(6, "<v^2> = " + rounded(*before, 12) + " at the start" +
                       (moving ? "; the drift report " + Report::waiting_for(4) : std::string("; nothing moves, no drift")));
  }
  if (before && advanced && *before > 0) {
    try {
      const double after = kinetic_energy(n, *velocities);
      correct_energy_drift(n, *velocities, *before);
      const double corrected = kinetic_energy(n, *velocities);
      report.done(6, "<v^2> before " + rounded(*before, 12) + ", after " + rounded(after, 12));
      report.done(6, "relative drift " + rounded(std::abs(after - *before) / *before, 3) + " without correction, " +
                         rounded(std::abs(corrected - *before) / *before, 3) + " after correct_energy_drift");
    } catch (const std::exception& error) {
      report.failed(6, error);
    }
  }
  return report.finish(staging);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options options = parse(argc, argv);
    if (options.help) {
      std::cout << help();
      return 0;
    }
    Staging staging(options.output);
    return run(options, staging);
  } catch (const BadInput& error) {
    std::cerr << "billiard: " << error.what() << "\n";
    return 2;
  } catch (const std::exception& error) {
    std::cerr << "billiard: unexpected error: " << printable(error.what()) << "\n";
    return 1;
  }
}
