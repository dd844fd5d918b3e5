// The `billiard` command: runs the six course functions on one table and reports.
//
//   billiard [TABLE_RADIUS CIRCLE_RADIUS N] [--seed S] [--collisions K]
//            [--drift-collisions M] [--output DIR]
//
// It places N circles (task 1), gives them velocities (task 2), draws the table (task 3),
// records a movie of K collisions (tasks 4 and 5), runs M more collisions and reports how
// well the mean squared velocity was conserved, before and after the correction (task 6).
// Built from a student's tasks/, it says which tasks are still missing and runs the others.
//
// Exit status: 0 all done; 1 some task is not implemented yet or failed; 2 bad input (one
// line on stderr, nothing written).
#include "billiard/course.hpp"
#include "billiard/not_implemented.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
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

constexpr const char* kUsage = "usage: billiard [TABLE_RADIUS CIRCLE_RADIUS N] [options]; see billiard --help";

constexpr const char* kHelp = R"(billiard: N hard circles colliding elastically on a circular table.

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
  --output DIR           folder for table.svg and movie.svg (default billiard-output);
                         open them in a web browser
  -h, --help             this help

limits: N <= 1000 (every collision checks all pairs); N x K <= 2,000,000 (movie size).
exit status: 0 done; 1 a task is not implemented yet or failed; 2 bad input.
)";

// Bad input: one line on stderr, exit status 2, nothing written.
struct BadInput : std::runtime_error {
  using std::runtime_error::runtime_error;
};

template <typename... Parts>
std::string text(const Parts&... parts) {
  std::ostringstream out;
  (out << ... << parts);
  return out.str();
}

double parse_number(std::string_view value, std::string_view name, std::string_view example) {
  double number = 0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), number);
  if (error != std::errc() || end != value.data() + value.size() || !std::isfinite(number) || number <= 0) {
    throw BadInput(text(name, " must be a positive number, got '", value, "' (for example ", example, "; ",
                        kUsage, ")"));
  }
  return number;
}

long long parse_whole(std::string_view value, std::string_view name, long long low, long long high,
                      std::string_view why) {
  long long number = 0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), number);
  if (error != std::errc() || end != value.data() + value.size() || number < low || number > high) {
    throw BadInput(text(name, " must be a whole number from ", low, " to ", high, why, ", got '", value, "' (",
                        kUsage, ")"));
  }
  return number;
}

bool looks_like_number(std::string_view argument) {
  return argument.size() > 1 && argument[0] == '-' && (std::isdigit(argument[1]) || argument[1] == '.');
}

struct Options {
  double table_radius = 10, circle_radius = 1;
  int n = 10;
  std::uint64_t seed = 1;
  int collisions = 100;
  long long drift_collisions = 10000;
  fs::path output = "billiard-output";
  bool help = false;
};

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
    } else if (name == "--seed" || name == "--collisions" || name == "--drift-collisions" || name == "--output") {
      if (k + 1 >= argc) throw BadInput(text(name, " needs a value (", kUsage, ")"));
      value = argv[++k];
    }
    if (name == "--seed") {
      options.seed = static_cast<std::uint64_t>(parse_whole(value, "--seed", 0, 9'000'000'000'000'000'000LL, ""));
    } else if (name == "--collisions") {
      options.collisions = static_cast<int>(parse_whole(value, "--collisions", 0, 1'000'000, ""));
    } else if (name == "--drift-collisions") {
      options.drift_collisions = parse_whole(value, "--drift-collisions", 0, 100'000'000, "");
    } else if (name == "--output") {
      if (value.empty()) throw BadInput(text("--output needs a folder name (", kUsage, ")"));
      options.output = fs::path(value);
    } else {
      throw BadInput(text("unknown option '", argument, "' (", kUsage, ")"));
    }
  }
  if (!numbers.empty() && numbers.size() != 3) {
    throw BadInput(text("expected three numbers TABLE_RADIUS CIRCLE_RADIUS N (or none for 10 1 10), got ",
                        numbers.size(), " (", kUsage, ")"));
  }
  if (numbers.size() == 3) {
    options.table_radius = parse_number(numbers[0], "TABLE_RADIUS", "10");
    options.circle_radius = parse_number(numbers[1], "CIRCLE_RADIUS", "1");
    options.n = static_cast<int>(parse_whole(numbers[2], "N", 0, 1000, " (every collision checks all pairs)"));
  }
  if (options.circle_radius >= options.table_radius) {
    throw BadInput(text("CIRCLE_RADIUS ", options.circle_radius, " must be smaller than TABLE_RADIUS ",
                        options.table_radius, " for a circle to fit on the table (", kUsage, ")"));
  }
  if (static_cast<long long>(options.n) * options.collisions > 2'000'000) {
    throw BadInput(text("--collisions ", options.collisions, " with N = ", options.n,
                        " makes too large a movie; use --collisions ", 2'000'000 / std::max(options.n, 1),
                        " or fewer (N x K <= 2,000,000)"));
  }
  std::error_code error;
  if (fs::exists(options.output, error) && !fs::is_directory(options.output, error)) {
    throw BadInput(text("--output ", options.output.string(), " is a file, not a folder; choose another folder"));
  }
  return options;
}

// Files are written into a private folder next to the output folder and moved into place at
// the end, so an interrupted or refused run leaves no partial output.
class Staging {
 public:
  explicit Staging(const fs::path& output) : output_(output) {
    const fs::path parent = fs::absolute(output).parent_path();
    fs::create_directories(parent);
    path_ = parent / text(".billiard-partial-", ::getpid());
    fs::create_directories(path_);
  }
  ~Staging() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  fs::path file(const std::string& name) const { return path_ / name; }
  // Moves the files written so far into the output folder; returns their final paths.
  std::vector<fs::path> publish() {
    std::vector<fs::path> published;
    if (fs::is_empty(path_)) return published;
    fs::create_directories(output_);
    for (const auto& entry : fs::directory_iterator(path_)) {
      const fs::path target = output_ / entry.path().filename();
      fs::rename(entry.path(), target);
      published.push_back(target);
    }
    return published;
  }

 private:
  fs::path output_, path_;
};

std::string format(double value, int precision = 6) {
  std::ostringstream out;
  out.precision(precision);
  out << value;
  return out.str();
}

struct Report {
  std::vector<std::string> missing;  // tasks not implemented yet, or failing
  void task_failed(const std::exception& error) {
    std::cout << "      !! " << error.what() << "\n";
    missing.push_back(error.what());
  }
  // Moves the files into place, says what was written and what is missing; the exit status.
  int finish(Staging& staging) const {
    for (const auto& file : staging.publish()) std::cout << "  wrote " << file.string() << "\n";
    if (missing.empty()) return 0;
    std::cout << "billiard: " << missing.size()
              << " step(s) could not run; the lines marked !! above say which task to work on\n";
    return 1;
  }
};

int run(const Options& options) {
  using namespace billiard;
  const double table_radius = options.table_radius, circle_radius = options.circle_radius;
  const int n = options.n;
  Rng rng(options.seed);
  Report report;

  // Task 1 first: an invalid_argument here means the circles cannot fit, which is bad input,
  // reported before anything is printed or written.
  std::optional<Coordinates> coordinates;
  std::optional<NotImplemented> init_missing;
  try {
    coordinates = init_billiard(table_radius, circle_radius, n, rng);
  } catch (const NotImplemented& missing) {
    init_missing = missing;
  } catch (const std::invalid_argument& error) {
    throw BadInput(error.what());
  }

  std::cout << "billiard: " << n << (n == 1 ? " circle" : " circles") << " of radius " << circle_radius
            << " on a table of radius " << table_radius << " (area fraction "
            << format(n * circle_radius * circle_radius / (table_radius * table_radius), 3) << "), seed "
            << options.seed << "\n";
  if (init_missing) report.task_failed(*init_missing);
  if (coordinates) std::cout << "  task 1 init_billiard     placed the circles\n";

  Staging staging(options.output);
  std::optional<Velocities> velocities;
  if (coordinates) {
    try {
      velocities = init_velocities(n, *coordinates, rng);
      std::cout << "  task 2 init_velocities   gave each circle a random velocity\n";
    } catch (const std::exception& error) {
      report.task_failed(error);
    }
    try {
      visualize_table(table_radius, circle_radius, n, *coordinates, staging.file("table.svg"));
      std::cout << "  task 3 visualize_table   drew the table: table.svg\n";
    } catch (const std::exception& error) {
      report.task_failed(error);
    }
  }
  if (!velocities) return report.finish(staging);

  std::optional<double> before;
  try {
    before = kinetic_energy(n, *velocities);
  } catch (const std::exception& error) {
    report.task_failed(error);
  }
  // With no circles, or all at rest, nothing ever collides: the movie is a still picture.
  const bool moving = n > 0 && velocities->squaredNorm() > 0;
  bool advanced = moving;
  try {
    movie(table_radius, circle_radius, n, *coordinates, *velocities, moving ? options.collisions : 0,
          staging.file("movie.svg"));
    std::cout << "  task 5 movie             recorded " << (moving ? options.collisions : 0)
              << " collisions: movie.svg\n";
  } catch (const NotImplemented& error) {
    report.task_failed(error);
    advanced = advanced && error.task_number() == 5;  // only movie is missing: propagate may work
  } catch (const std::exception& error) {
    report.task_failed(error);
    advanced = false;
  }
  if (!moving) std::cout << "  task 4 propagate         nothing moves, so nothing collides\n";
  try {
    double elapsed = 0;
    for (long long k = 0; advanced && k < options.drift_collisions; ++k) {
      elapsed += propagate(table_radius, circle_radius, n, *coordinates, *velocities).time;
    }
    if (advanced) {
      std::cout << "  task 4 propagate         " << options.drift_collisions << " more collisions, simulated time "
                << format(elapsed) << "\n";
    }
  } catch (const std::exception& error) {
    report.task_failed(error);
    advanced = false;
  }
  if (before && advanced && *before > 0) {
    try {
      const double after = kinetic_energy(n, *velocities);
      correct_energy_drift(n, *velocities, *before);
      const double corrected = kinetic_energy(n, *velocities);
      std::cout << "  task 6 kinetic_energy    <v^2> before " << format(*before, 12) << ", after "
                << format(after, 12) << "\n"
                << "                           relative drift " << format(std::abs(after - *before) / *before, 3)
                << " without correction, " << format(std::abs(corrected - *before) / *before, 3)
                << " after correct_energy_drift\n";
    } catch (const std::exception& error) {
      report.task_failed(error);
    }
  }
  return report.finish(staging);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options options = parse(argc, argv);
    if (options.help) {
      std::cout << kHelp;
      return 0;
    }
    return run(options);
  } catch (const BadInput& error) {
    std::cerr << "billiard: " << error.what() << "\n";
    return 2;
  } catch (const std::exception& error) {
    std::cerr << "billiard: unexpected error: " << error.what() << "\n";
    return 1;
  }
}
