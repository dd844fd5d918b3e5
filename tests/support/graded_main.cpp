// main() of every graded suite. Runs GoogleTest as usual; with --expect-not-implemented it
// instead checks the untouched stubs: it succeeds only if every test failed, and each failed
// with the stub's "not implemented yet" error (so no test can pass without the student's code).
#include <gtest/gtest.h>

#include <cstring>
#include <iostream>
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

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  bool expect_not_implemented = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--expect-not-implemented") == 0) expect_not_implemented = true;
  }
  if (!expect_not_implemented) return RUN_ALL_TESTS();

  auto* checker = new StubChecker;  // owned by GoogleTest's listener list
  ::testing::UnitTest::GetInstance()->listeners().Append(checker);
  RUN_ALL_TESTS();
  return checker->report() ? 0 : 1;
}
