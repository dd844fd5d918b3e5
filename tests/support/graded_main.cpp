// main() of every graded suite. Runs GoogleTest as usual, plus three modes:
//
//   --list-graded           print each test's points and visibility as one JSON object per
//                           line, for the grader; fail if some test carries no points.
//   --graded-result=PATH    after the tests, write "<token> passed" or "<token> failed" to
//                           PATH, where <token> is the secret the grader passes in the
//                           environment variable BILLIARD_GRADER_TOKEN. The variable is wiped
//                           before any test runs, so code under test cannot forge the line; a
//                           test that exits early, crashes or hangs writes nothing (no points).
//   --expect-not-implemented
//                           check the untouched stubs: succeed only if every test failed, and
//                           each with the stub's "not implemented yet" error (so no test can
//                           pass without the student's code).
//   --brief                 print only what failed, each failure as its message: a task that
//                           is not written yet gives one line per test (CTest passes this, so
//                           that a first run on the stubs reads as a list, not as pages).
#include "support/graded.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <set>
#include <string>
#include <vector>

namespace {

constexpr const char* kStubMessage = "not implemented yet";

class StubChecker : public ::testing::EmptyTestEventListener {
 public:
  void OnTestStart(const ::testing::TestInfo&) override { saw_stub_message_ = false; }

  void OnTestPartResult(const ::testing::TestPartResult& result) override {
    if (result.failed() && std::strstr(result.message(), kStubMessage) != nullptr) saw_stub_message_ = true;
  }

  void OnTestEnd(const ::testing::TestInfo& info) override {
    ++tests_;
    const std::string name = std::string(info.test_suite_name()) + "." + info.name();
    if (info.result()->Passed()) {
      problems_.push_back(name + " passed although the task is only a stub");
    } else if (!saw_stub_message_) {
      problems_.push_back(name + " failed without the \"" + kStubMessage + "\" message");
    }
  }

  bool report() const {
    if (tests_ == 0) {
      std::cout << "stub check: no tests ran\n";
      return false;
    }
    for (const auto& problem : problems_) std::cout << "stub check: " << problem << "\n";
    std::cout << "stub check: " << tests_ - problems_.size() << " of " << tests_
              << " tests failed with the \"" << kStubMessage << "\" message, as they should\n";
    return problems_.empty();
  }

 private:
  bool saw_stub_message_ = false;
  int tests_ = 0;
  std::vector<std::string> problems_;
};

// GoogleTest's printer without its banners. For each failing test: its first failure, from the
// student's message (explain(): Expected / Your code / Hint) when it has one, else GoogleTest's
// own; for the stubs' "not implemented yet" exception only that exception's one-line message;
// then how many more checks failed the same way.
class BriefPrinter : public ::testing::EmptyTestEventListener {
 public:
  void OnTestStart(const ::testing::TestInfo&) override { failures_ = 0; }

  void OnTestPartResult(const ::testing::TestPartResult& result) override {
    if (!result.failed() || failures_++ > 0) return;
    const std::string message = result.message();
    const std::string quoted = "C++ exception with description \"";
    if (message.find(kStubMessage) != std::string::npos && message.rfind(quoted, 0) == 0) {
      const auto end = message.find("\" thrown in");
      std::cout << message.substr(quoted.size(), end == std::string::npos ? end : end - quoted.size()) << "\n";
      return;
    }
    if (result.file_name() != nullptr) std::cout << result.file_name() << ":" << result.line_number() << ": ";
    const auto got = message.find("\nYour code: ");
    const auto students = got == std::string::npos ? got : message.rfind("\nExpected: ", got);
    std::cout << "failed\n" << (students == std::string::npos ? message : message.substr(students + 1)) << "\n";
  }

  void OnTestEnd(const ::testing::TestInfo&) override {
    if (failures_ > 1) std::cout << "(and " << failures_ - 1 << " more failed checks in this test)\n";
  }

 private:
  int failures_ = 0;
};

// Prints the graded tests as JSON lines; false if a test of the binary has no points or a
// registration names no test.
bool list_graded() {
  std::set<std::string> in_binary;
  const auto* unit = ::testing::UnitTest::GetInstance();
  for (int i = 0; i < unit->total_test_suite_count(); ++i) {
    const auto* suite = unit->GetTestSuite(i);
    for (int j = 0; j < suite->total_test_count(); ++j) {
      in_binary.insert(std::string(suite->name()) + "." + suite->GetTestInfo(j)->name());
    }
  }
  bool ok = true;
  std::set<std::string> graded;
  for (const auto& test : billiard::testing::graded_tests()) {
    graded.insert(test.name);
    std::cout << "{\"test\": \"" << test.name << "\", \"points\": " << test.points << ", \"visibility\": \""
              << billiard::testing::to_string(test.visibility) << "\"}\n";
    if (!in_binary.count(test.name)) ok = false;
  }
  for (const auto& name : in_binary) {
    if (!graded.count(name)) {
      std::cerr << "graded suite: " << name << " has no points; declare it with GRADED_TEST\n";
      ok = false;
    }
  }
  return ok;
}

// Reads and wipes the grader's secret, so that code under test cannot find it in the
// environment.
std::string take_grader_token() {
  char* value = std::getenv("BILLIARD_GRADER_TOKEN");
  if (value == nullptr) return "";
  std::string token = value;
  std::memset(value, 0, std::strlen(value));
  unsetenv("BILLIARD_GRADER_TOKEN");
  return token;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string token = take_grader_token();
  ::testing::InitGoogleTest(&argc, argv);
  bool expect_not_implemented = false, list = false;
  std::string result_path;
  for (int i = 1; i < argc; ++i) {
    const std::string argument = argv[i];
    if (argument == "--expect-not-implemented") expect_not_implemented = true;
    if (argument == "--list-graded") list = true;
    if (argument.rfind("--graded-result=", 0) == 0) result_path = argument.substr(16);
    if (argument == "--brief") {
      auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
      delete listeners.Release(listeners.default_result_printer());
      listeners.Append(new BriefPrinter);  // owned by GoogleTest's listener list
    }
  }
  if (list) return list_graded() ? 0 : 1;
  if (expect_not_implemented) {
    auto* checker = new StubChecker;  // owned by GoogleTest's listener list
    ::testing::UnitTest::GetInstance()->listeners().Append(checker);
    const int ignored = RUN_ALL_TESTS();  // the checker decides, not the failures it expects
    (void)ignored;
    return checker->report() ? 0 : 1;
  }
  const int status = RUN_ALL_TESTS();
  if (!result_path.empty()) {
    const auto* unit = ::testing::UnitTest::GetInstance();
    const bool passed = status == 0 && unit->Passed() && unit->test_to_run_count() > 0;
    std::ofstream(result_path) << token << (passed ? " passed\n" : " failed\n");
  }
  return status;
}
