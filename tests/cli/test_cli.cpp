// The `billiard` command as a person uses it: what it prints, its exit status, and which files
// it leaves behind. Each test runs the command in a fresh, empty folder.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Result {
  int status = -1;
  std::string out, err;
  std::vector<std::string> files;  // everything left in the folder, recursively, relative paths
};

std::string slurp(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device entropy;
    folder_ = fs::temp_directory_path() / ("billiard-cli-" + std::to_string(entropy()));
    fs::create_directories(folder_ / "work");
  }
  void TearDown() override { fs::remove_all(folder_); }

  // Runs `exe arguments` inside folder_/work; stdout and stderr go to files outside it.
  Result run(const std::string& exe, const std::string& arguments) {
    const std::string command = "cd '" + (folder_ / "work").string() + "' && '" + exe + "' " + arguments + " >'" +
                                (folder_ / "out").string() + "' 2>'" + (folder_ / "err").string() + "'";
    const int raw = std::system(command.c_str());
    Result result;
    result.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    result.out = slurp(folder_ / "out");
    result.err = slurp(folder_ / "err");
    for (const auto& entry : fs::recursive_directory_iterator(folder_ / "work")) {
      result.files.push_back(fs::relative(entry.path(), folder_ / "work").string());
    }
    return result;
  }

  // Bad input: status 2, exactly one line on stderr naming the problem, nothing on stdout,
  // and no file or folder left behind.
  void expect_refused(const std::string& arguments, const std::string& must_mention) {
    SCOPED_TRACE("billiard " + arguments);
    const Result result = run(BILLIARD_EXE, arguments);
    EXPECT_EQ(result.status, 2);
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
    EXPECT_EQ(result.err.rfind("billiard: ", 0), 0u) << result.err;
    EXPECT_NE(result.err.find(must_mention), std::string::npos) << result.err;
    EXPECT_EQ(result.out, "");
    EXPECT_TRUE(result.files.empty()) << "left behind: " << result.files.front();
  }

  fs::path folder_;
};

double number_after(const std::string& text, const std::string& label) {
  std::smatch match;
  const std::regex pattern(label + R"(\s*([-+0-9.eE]+))");
  if (!std::regex_search(text, match, pattern)) return -1;
  return std::stod(match[1]);
}

TEST_F(Cli, DefaultTableRunsAllSixTasksAndWritesBothPictures) {
  const Result result = run(BILLIARD_EXE, "10 1 10");
  ASSERT_EQ(result.status, 0) << result.out << result.err;
  EXPECT_EQ(result.err, "");
  for (const char* task : {"task 1", "task 2", "task 3", "task 4", "task 5", "task 6"}) {
    EXPECT_NE(result.out.find(task), std::string::npos) << task << " missing from:\n" << result.out;
  }
  const std::string table = slurp(folder_ / "work/billiard-output/table.svg");
  const std::string movie = slurp(folder_ / "work/billiard-output/movie.svg");
  // 1 table + 10 circles, and the movie animates every circle's cx and cy.
  const std::regex circle("<circle\\b");
  EXPECT_EQ(std::distance(std::sregex_iterator(table.begin(), table.end(), circle), std::sregex_iterator()), 11);
  const std::regex animate("<animate\\b");
  EXPECT_EQ(std::distance(std::sregex_iterator(movie.begin(), movie.end(), animate), std::sregex_iterator()), 20);
}

TEST_F(Cli, ReportsEnergyDriftBelowRoundingLevel) {
  // 10,100 collisions of exact event-driven dynamics: rounding only, far below 1e-10.
  const Result result = run(BILLIARD_EXE, "10 1 10 --seed 7");
  ASSERT_EQ(result.status, 0) << result.out << result.err;
  const double drift = number_after(result.out, "relative drift");
  EXPECT_GE(drift, 0) << result.out;
  EXPECT_LT(drift, 1e-10) << result.out;
  const double corrected = number_after(result.out, "without correction,");
  EXPECT_GE(corrected, 0) << result.out;
  EXPECT_LT(corrected, 1e-14) << result.out;
}

TEST_F(Cli, SameSeedSameReportDifferentSeedDifferentTable) {
  const Result first = run(BILLIARD_EXE, "10 1 10 --seed 3 --output a");
  const Result again = run(BILLIARD_EXE, "10 1 10 --seed 3 --output b");
  const Result other = run(BILLIARD_EXE, "10 1 10 --seed 4 --output c");
  ASSERT_EQ(first.status, 0);
  EXPECT_EQ(slurp(folder_ / "work/a/table.svg"), slurp(folder_ / "work/b/table.svg"));
  EXPECT_NE(slurp(folder_ / "work/a/table.svg"), slurp(folder_ / "work/c/table.svg"));
}

TEST_F(Cli, OptionsChooseOutputFolderAndMovieLength) {
  const Result result = run(BILLIARD_EXE, "8 0.5 20 --collisions=7 --drift-collisions 10 --output pictures/run1");
  ASSERT_EQ(result.status, 0) << result.out << result.err;
  const std::string movie = slurp(folder_ / "work/pictures/run1/movie.svg");
  // 7 collisions: 8 key frames, so 7 semicolons in each values list.
  std::smatch values;
  ASSERT_TRUE(std::regex_search(movie, values, std::regex("values=\"([^\"]*)\"")));
  const std::string list = values[1];
  EXPECT_EQ(std::count(list.begin(), list.end(), ';'), 7);
}

TEST_F(Cli, HelpExplainsUsageAndExitsZero) {
  const Result result = run(BILLIARD_EXE, "--help");
  EXPECT_EQ(result.status, 0);
  for (const char* word : {"TABLE_RADIUS", "--seed", "--collisions", "--output", "exit status"}) {
    EXPECT_NE(result.out.find(word), std::string::npos) << word;
  }
  EXPECT_TRUE(result.files.empty());
}

TEST_F(Cli, TooManyCirclesForTheTableIsRefused) { expect_refused("10 1 1000", "cannot fit"); }
TEST_F(Cli, NegativeRadiusIsRefused) { expect_refused("-1 1 10", "TABLE_RADIUS"); }
TEST_F(Cli, WordInsteadOfNumberIsRefused) { expect_refused("ten 1 10", "TABLE_RADIUS"); }
TEST_F(Cli, FractionalCountIsRefused) { expect_refused("10 1 2.5", "N"); }
TEST_F(Cli, CircleLargerThanTableIsRefused) { expect_refused("10 12 1", "CIRCLE_RADIUS"); }
TEST_F(Cli, TwoNumbersInsteadOfThreeAreRefused) { expect_refused("10 1", "three numbers"); }
TEST_F(Cli, UnknownOptionIsRefused) { expect_refused("10 1 10 --sed 4", "--sed"); }
TEST_F(Cli, BadSeedIsRefused) { expect_refused("10 1 10 --seed x", "--seed"); }
TEST_F(Cli, NegativeCollisionsAreRefused) { expect_refused("10 1 10 --collisions -3", "--collisions"); }
TEST_F(Cli, OversizedMovieIsRefused) { expect_refused("100 1 1000 --collisions 100000", "--collisions"); }
TEST_F(Cli, TooManyCirclesForAllPairsCodeAreRefused) { expect_refused("1000 1 5000", "N"); }
TEST_F(Cli, MissingOptionValueIsRefused) { expect_refused("10 1 10 --output", "--output"); }

TEST_F(Cli, OutputThatIsAFileIsRefused) {
  std::ofstream(folder_ / "work/taken") << "not a folder";
  const Result result = run(BILLIARD_EXE, "--output taken");
  EXPECT_EQ(result.status, 2);
  EXPECT_NE(result.err.find("taken"), std::string::npos) << result.err;
  EXPECT_EQ(slurp(folder_ / "work/taken"), "not a folder");
  EXPECT_EQ(result.files.size(), 1u);
}

TEST_F(Cli, NoCirclesGivesStillPicturesAndNoError) {
  const Result result = run(BILLIARD_EXE, "10 1 0");
  EXPECT_EQ(result.status, 0) << result.out << result.err;
  EXPECT_TRUE(fs::exists(folder_ / "work/billiard-output/table.svg"));
  EXPECT_TRUE(fs::exists(folder_ / "work/billiard-output/movie.svg"));
}

#ifdef BILLIARD_STUBS_EXE
TEST_F(Cli, BuiltFromStubsItNamesTheMissingTaskInsteadOfCrashing) {
  const Result result = run(BILLIARD_STUBS_EXE, "10 1 10");
  EXPECT_EQ(result.status, 1) << result.out << result.err;
  EXPECT_NE(result.out.find("task 1 (init_billiard) is not implemented yet"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("tasks/init_billiard.cpp"), std::string::npos) << result.out;
  EXPECT_TRUE(result.files.empty());
}
#endif

}  // namespace
