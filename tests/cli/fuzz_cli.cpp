// Fuzz test of the `billiard` command line: generated argument vectors (numbers at and beyond
// the limits, garbage, missing values, repeated and unknown options, odd and unwritable output
// folders), each run in a fresh folder. Whatever the input, the command built from the
// reference solutions must
//   - end by itself within kRunLimit seconds, with exit status 0 or 2 (never 1: the reference
//     tasks never fail; never a signal);
//   - on exit 2, print exactly one line on stderr, nothing on stdout, and leave every folder
//     as it was (nothing created, nothing changed);
//   - on exit 0, either print the help and write nothing, or write exactly table.svg and
//     movie.svg, complete, into one folder, and change nothing else.
// The command built from the untouched stubs, where it is built, must give the same refusals
// (same line) and otherwise exit 1 without writing anything.
//
// The vectors come from a fixed seed, so a failure can be reproduced; BILLIARD_CLI_FUZZ_SEED
// and BILLIARD_CLI_FUZZ_VECTORS choose others. Accepted runs are kept short: most vectors end
// with small --drift-collisions and --collisions, and the others use at most 50 circles.
#include "cli_runner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

constexpr std::uint64_t kSeed = 2718281828;
constexpr int kVectors = 600;
constexpr double kRunLimit = 20;  // seconds; the slowest accepted vector takes well under one

using Rng = std::mt19937_64;

// Values that the command accepts (though some may still be refused in combination: circles
// that do not fit, too big a movie) and values that it refuses.
struct Pool {
  std::vector<std::string> valid, invalid;
};

// Strings that parse as nothing, or as something else than intended.
const std::vector<std::string> kGarbage = {"",    " ",     "ten",  "10abc", "1e",  ".",        "-",       "--",
                                           "1,5", "1_000", "0x10", "0X1p3", "+5",  " 5",       "5 ",      "\t5",
                                           "5\n", "inf",   "-inf", "nan",   "NaN", "infinity", "1e99999", "\xc3\xa9"};
const Pool kRadii = {{"10", "1", "0.5", "2", "3.25", "0.001", "1000", "999.9999999", "0.0010000001", "9.9999999999",
                      "1e3", "1E-3", "000010", "10.", ".5"},
                     {"1000.0000001", "0.0009999999", "0", "-0", "-1", "1e308", "1.7976931348623157e308", "1e-308",
                      "2.2250738585072014e-308", "4.9e-324", "1e-320", "2147483648", "99999999999999999999999"}};
const Pool kCounts = {{"0", "1", "2", "10", "999", "1000", "-0", "010"},
                      {"1001", "-1", "2147483647", "2147483648", "-2147483649", "4294967296", "9223372036854775807",
                       "9223372036854775808", "1e3", "2.5", "+3"}};
const Pool kSmallCounts = {{"0", "1", "2", "3", "10", "50", "-0"}, {"-1", "1001", "1e1", "2.5"}};
const Pool kSeeds = {{"0", "1", "42", "9000000000000000000"},
                     {"-1", "9000000000000000001", "18446744073709551615", "18446744073709551616", "3.0", "x"}};
// Only small counts are valid here, so that every accepted run is short; the invalid ones
// include the first values beyond the limits.
const Pool kCollisions = {{"0", "1", "2", "5", "-0", "007"},
                          {"-1", "1000001", "2147483648", "9223372036854775808", "1e2", "1.5"}};
const Pool kDriftCollisions = {{"0", "1", "3", "20", "-0"},
                               {"-1", "100000001", "2147483648", "18446744073709551616", "1e4", "0.5"}};
// Relative to the folder the command runs in; {case} is the absolute path of the case's folder.
// "locked" has no write permission, which stops everyone but root.
const Pool kOutputs = {
    {"out", "a/b/c", "a//b/", "./x/../y", ".", "..", "existing", "existing/", "locked", "locked/new", "-", "--seed",
     "with space", "new\nline", "tab\there", "\xc3\xbcn\xc3\xaf", "{case}/absolute", std::string(NAME_MAX, 'n')},
    {"has-table", "taken", "taken/x", "file-link", "file-link/x", "dangling", "{case}/work/taken/x",
     std::string(NAME_MAX + 1, 'n'), "deep/" + std::string(NAME_MAX + 1, 'n') + "/x", "/proc/billiard-fuzz", "/proc",
     "/proc/self/billiard-fuzz", "/dev/null", "/dev/null/x", ""}};
const std::vector<std::string> kUnknown = {"--sed",        "--SEED",      "---seed", "--seeds",  "-s",
                                           "-x",           "--",          "-",       "--help=1", "-hh",
                                           "--output-dir", "--collision", "-inf",    "-nan",     "--=5"};

struct Generator {
  Rng rng;
  bool plausible = false;  // this vector draws valid values only (but in any combination)

  bool chance(double p) { return std::uniform_real_distribution<double>(0, 1)(rng) < p; }
  int below(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng); }
  const std::string& pick(const std::vector<std::string>& pool) { return pool[std::size_t(below(int(pool.size())))]; }
  const std::string& pick(const Pool& pool) {
    if (plausible || chance(0.5)) return pick(pool.valid);
    return chance(0.8) ? pick(pool.invalid) : pick(kGarbage);
  }

  // A random number as text: log-uniform over many orders of magnitude, whole or not.
  std::string random_number(double low_exponent, double high_exponent, bool whole) {
    const double value = std::pow(10.0, std::uniform_real_distribution<double>(low_exponent, high_exponent)(rng));
    char buffer[64];
    if (whole) {
      std::snprintf(buffer, sizeof buffer, "%.0f", value);
    } else {
      std::snprintf(buffer, sizeof buffer, chance(0.5) ? "%g" : "%.17g", value);
    }
    return buffer;
  }
  std::string radius() {
    if (chance(0.6)) return pick(kRadii);
    return plausible ? random_number(-3, 3, false) : random_number(-5, 5, false);
  }
  std::string count(bool small) {
    if (small) return pick(kSmallCounts);
    if (chance(0.6)) return pick(kCounts);
    return plausible ? random_number(0, 3, true) : random_number(0, 3.1, true);
  }
  std::vector<std::string> option() {
    struct Kind {
      const char* name;
      const Pool* values;
    };
    static const Kind kinds[] = {{"--seed", &kSeeds},
                                 {"--collisions", &kCollisions},
                                 {"--drift-collisions", &kDriftCollisions},
                                 {"--output", &kOutputs}};
    const double roll = std::uniform_real_distribution<double>(0, 1)(rng);
    if (roll < 0.02) return {chance(0.5) ? "-h" : "--help"};
    if (roll < 0.12 && !plausible) return {pick(kUnknown)};
    const Kind& kind = kinds[below(4)];
    const std::string value = pick(*kind.values);
    if (roll < 0.2 && !plausible) return {kind.name};  // no value: takes the next argument, or none is left
    if (roll < 0.45) return {std::string(kind.name) + "=" + value};
    return {kind.name, value};
  }

  std::vector<std::string> next() {
    plausible = chance(0.4);
    // Most vectors end with a short run; the others keep N small, so that they are short too.
    const bool short_run = chance(0.85);
    std::vector<std::vector<std::string>> parts;
    const int numbers = chance(plausible ? 0.8 : 0.6) ? 3 : std::vector<int>{0, 0, 0, 1, 2, 4}[std::size_t(below(6))];
    for (int k = 0; k < numbers; ++k) {
      parts.push_back({k == 2 ? count(!short_run) : k < 2 ? radius() : count(true)});
    }
    if (plausible && numbers >= 2 && std::stod(parts[0][0]) < std::stod(parts[1][0])) {
      std::swap(parts[0], parts[1]);  // the table larger than the circles, most of the time
    }
    const int options = below(chance(0.2) ? 6 : 3);
    for (int k = 0; k < options; ++k) parts.push_back(option());
    // Numbers and options in any order, except that the numbers keep theirs.
    std::vector<std::string> arguments;
    std::vector<std::size_t> order(parts.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::shuffle(order.begin(), order.end(), rng);
    std::size_t next_number = 0;
    for (const std::size_t k : order) {
      const auto& part = k < std::size_t(numbers) ? parts[next_number++] : parts[k];
      arguments.insert(arguments.end(), part.begin(), part.end());
    }
    if (short_run) {
      for (const std::string& argument : {std::string("--drift-collisions"), std::to_string(below(21)),
                                          std::string("--collisions"), std::to_string(below(6))}) {
        arguments.push_back(argument);
      }
    }
    return arguments;
  }
};

// A fresh folder for one run, with the odd things the output paths point at.
fs::path make_case(const fs::path& root, const std::string& name) {
  const fs::path folder = root / name;
  fs::create_directories(folder / "work/existing");
  std::ofstream(folder / "work/existing/notes.txt") << "kept";
  std::ofstream(folder / "work/taken") << "a file, not a folder";
  fs::create_directories(folder / "work/has-table/table.svg");
  fs::create_directories(folder / "work/locked");
  fs::permissions(folder / "work/locked", fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                                              fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
  fs::create_symlink("nowhere", folder / "work/dangling");
  fs::create_symlink("taken", folder / "work/file-link");
  return folder;
}

void remove_case(const fs::path& folder) {
  std::error_code ignored;
  fs::permissions(folder / "work/locked", fs::perms::owner_all, fs::perm_options::add, ignored);
  fs::remove_all(folder, ignored);
}

bool is_help(const cli::Run& run) { return run.out.find("\nusage: billiard") != std::string::npos; }

// What is wrong with an exit 0 run that wrote pictures: `before` and `after` are the case's
// folder; exactly one table.svg and one movie.svg, in one folder, are new, complete SVG files,
// and nothing else changed but new folders (not the command's private one).
std::string written_problems(const std::map<std::string, std::string>& before,
                             const std::map<std::string, std::string>& after) {
  std::string problems;
  for (const auto& [name, content] : before) {
    const auto now = after.find(name);
    if (now == after.end()) {
      problems += name + " was removed; ";
    } else if (now->second != content) {
      problems += name + " was changed; ";
    }
  }
  std::set<std::string> folders_with_table, folders_with_movie;
  for (const auto& [name, content] : after) {
    if (before.count(name)) continue;
    if (name.find(".billiard-partial") != std::string::npos) {
      problems += "the private folder " + name + " was left behind; ";
      continue;
    }
    if (content == "<folder>") continue;
    const fs::path path(name);
    const std::string file = path.filename().string();
    if (file != "table.svg" && file != "movie.svg") {
      problems += "unexpected new file " + name + "; ";
      continue;
    }
    (file == "table.svg" ? folders_with_table : folders_with_movie).insert(path.parent_path().string());
    if (content.rfind("<?xml", 0) != 0 || content.size() < 7 || content.substr(content.size() - 7) != "</svg>\n") {
      problems += name + " is not a complete SVG file; ";
    }
  }
  if (folders_with_table.size() != 1 || folders_with_table != folders_with_movie) {
    problems += "expected one new table.svg and one new movie.svg in one folder; ";
  }
  return problems;
}

std::uint64_t from_environment(const char* name, std::uint64_t fallback) {
  const char* value = std::getenv(name);
  return value && *value ? std::strtoull(value, nullptr, 10) : fallback;
}

TEST(CliFuzz, EveryArgumentVectorEndsInExitZeroOrACleanRefusal) {
  const std::uint64_t seed = from_environment("BILLIARD_CLI_FUZZ_SEED", kSeed);
  const auto vectors = static_cast<int>(from_environment("BILLIARD_CLI_FUZZ_VECTORS", kVectors));
  std::random_device entropy;
  const fs::path root = fs::temp_directory_path() / ("billiard-cli-fuzz-" + std::to_string(entropy()));
  fs::create_directories(root / "logs");
  std::cout << "cli fuzz: seed " << seed << " (set BILLIARD_CLI_FUZZ_SEED to change it)" << std::endl;

  Generator generator{Rng(seed)};
  int refused = 0, done = 0, help = 0, crashes = 0, failures = 0, stubs_missing = 0, stubs_refused = 0;
  double slowest = 0, total = 0;
  std::string slowest_vector;
  const auto fail = [&](int index, const std::vector<std::string>& arguments, const std::string& what) {
    ++failures;
    if (failures <= 20) {
      ADD_FAILURE() << "seed " << seed << ", vector " << index << ": billiard " << cli::shown(arguments) << "\n  "
                    << what;
    }
  };
  cli::Limits limits;
  limits.seconds = kRunLimit;

  for (int index = 0; index < vectors; ++index) {
    std::vector<std::string> arguments = generator.next();
    const fs::path folder = make_case(root, "case");
    for (auto& argument : arguments) {
      for (std::size_t at; (at = argument.find("{case}")) != std::string::npos;) {
        argument.replace(at, 6, folder.string());
      }
    }
    const auto before = cli::tree(folder);
    const cli::Run run = cli::run_program(BILLIARD_EXE, arguments, folder / "work", root / "logs/run", limits);
    const auto after = cli::tree(folder);
    total += run.seconds;
    if (run.seconds > slowest) {
      slowest = run.seconds;
      slowest_vector = cli::shown(arguments);
    }
    const std::string output = "stdout:\n" + run.out + "stderr:\n" + run.err;
    if (run.timed_out || run.signal != 0 || (run.status != 0 && run.status != 2)) {
      ++crashes;
      fail(index, arguments,
           run.timed_out ? "ran longer than " + std::to_string(kRunLimit) + " s"
           : run.signal  ? "ended by signal " + std::to_string(run.signal)
                         : "exit status " + std::to_string(run.status) + ", expected 0 or 2\n" + output);
    } else if (run.status == 2) {
      ++refused;
      const std::string problems = cli::refusal_problems(run);
      if (!problems.empty()) fail(index, arguments, problems + "\n" + output);
      if (after != before) fail(index, arguments, "refused, but the folders changed");
    } else if (is_help(run)) {
      ++done;
      ++help;
      if (after != before || !run.err.empty()) fail(index, arguments, "help, but wrote something\n" + output);
    } else {
      ++done;
      std::string problems = written_problems(before, after);
      if (!run.err.empty()) problems += "stderr is not empty; ";
      if (!problems.empty()) fail(index, arguments, problems + "\n" + output);
    }
    remove_case(folder);

#ifdef BILLIARD_STUBS_EXE
    // The stubs refuse the same input with the same line (the checks are the command's own);
    // what passes them reaches task 1, which is missing: exit 1 and nothing written.
    const fs::path stubs_folder = make_case(root, "case");
    const auto stubs_before = cli::tree(stubs_folder);
    const cli::Run stubs =
        cli::run_program(BILLIARD_STUBS_EXE, arguments, stubs_folder / "work", root / "logs/stubs", limits);
    const bool stubs_unchanged = cli::tree(stubs_folder) == stubs_before;
    remove_case(stubs_folder);
    const std::string stubs_output = "stubs' stdout:\n" + stubs.out + "stubs' stderr:\n" + stubs.err;
    if (stubs.timed_out || stubs.signal != 0) {
      fail(index, arguments, "the stubs' command crashed or hung\n" + stubs_output);
    } else if (is_help(run)) {
      if (stubs.status != 0 || stubs.out != run.out) fail(index, arguments, "the stubs' command gave no help");
    } else if (stubs.status == 2) {
      ++stubs_refused;
      if (run.status != 2 || stubs.err != run.err) {
        fail(index, arguments, "the stubs' command refused it differently\n" + output + stubs_output);
      }
    } else if (stubs.status == 1) {
      ++stubs_missing;
      if (!stubs.err.empty() || stubs.out.find("is not implemented yet") == std::string::npos) {
        fail(index, arguments, "the stubs' command did not name the missing task\n" + stubs_output);
      }
    } else {
      fail(index, arguments, "the stubs' command exited " + std::to_string(stubs.status) + "\n" + stubs_output);
    }
    if (!stubs_unchanged) fail(index, arguments, "the stubs' command wrote something");
#endif
  }
  fs::remove_all(root);

  std::cout << "cli fuzz: " << vectors << " argument vectors, " << refused << " exit 2, " << done << " exit 0 (" << help
            << " of them help), " << crashes << " crashes or other exits; reference runs " << total
            << " s in all, slowest " << slowest << " s: billiard " << slowest_vector << std::endl;
#ifdef BILLIARD_STUBS_EXE
  std::cout << "cli fuzz, built from the stubs: " << stubs_missing << " exit 1, " << stubs_refused << " exit 2"
            << std::endl;
#endif
  EXPECT_EQ(failures, 0) << "seed " << seed;
  // The generator must reach both outcomes often, or the test checks little.
  EXPECT_GT(refused, vectors / 4);
  EXPECT_GT(done - help, vectors / 10);
}

}  // namespace
