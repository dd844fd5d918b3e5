// main() of every graded suite. Runs GoogleTest as usual, plus three modes:
//
//   --list-graded           print each test's points and visibility as one JSON object per
//                           line, for the grader; fail if some test carries no points.
//   --expect-not-implemented
//                           check the untouched stubs: succeed only if every test failed, and
//                           each with the stub's "not implemented yet" error (so no test can
//                           pass without the student's code).
//   --brief                 print only what failed, each failure as its message: a task that
//                           is not written yet gives one line per test (CTest passes this, so
//                           that a first run on the stubs reads as a list, not as pages).
//   --serve=FD              the grader's test server (tests/grader/grade.py). FD is a socket of
//                           datagrams (SOCK_SEQPACKET) to the grader, one message each way:
//                             grader: "NAME FOLDER CPU_SECONDS [VARIABLE=VALUE...]", with the
//                                     test's pipes to and from its worker attached (SCM_RIGHTS)
//                             server: "ready" once, then for each test "started PID", the
//                                     test's own "verdict passed" or "verdict failed", and
//                                     "ended WAIT_STATUS CPU_MICROSECONDS"
//                           Each test runs in a process of its own, forked from this one before
//                           any test ran (so it starts as a new process of the program would, at a
//                           fraction of the cost), in its own process group, in FOLDER (relative
//                           to this program's working folder; also its HOME and TMPDIR), with
//                           those variables set, at most CPU_SECONDS (rounded up) of computing,
//                           its output on this program's, and the course's functions called in
//                           its worker (support/student_code.hpp). Ends when the grader closes FD.
//
// Under the grader this program is the judge: it holds no submitted code (the course's functions
// are proxies to the worker), so its verdicts cannot be forged from there.
#include "support/failure_pictures.hpp"
#include "support/graded.hpp"
#include "support/student_code.hpp"

#include <gtest/gtest.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
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

// Sends one message to the grader.
void report(int grader, const std::string& message) {
  while (::send(grader, message.data(), message.size(), MSG_NOSIGNAL) < 0) {
    if (errno != EINTR) std::_Exit(3);  // the grader has gone
  }
}

// The pipes of a test to and from its worker, as the grader attaches them to its message.
struct Worker {
  int to = -1, from = -1;
  void close() {
    for (int fd : {to, from}) {
      if (fd >= 0) ::close(fd);
    }
    to = from = -1;
  }
};

// Receives one message from the grader and the descriptors attached to it; false when the
// grader has closed the socket.
bool receive(int grader, std::string& message, Worker& worker) {
  char text[8192];
  alignas(cmsghdr) char control[CMSG_SPACE(2 * sizeof(int))];
  iovec part{text, sizeof text};
  msghdr header{};
  header.msg_iov = &part;
  header.msg_iovlen = 1;
  header.msg_control = control;
  header.msg_controllen = sizeof control;
  ssize_t size;
  while ((size = ::recvmsg(grader, &header, MSG_CMSG_CLOEXEC)) < 0 && errno == EINTR) {
  }
  if (size <= 0) return false;
  message.assign(text, static_cast<std::size_t>(size));
  worker = Worker{};
  for (cmsghdr* item = CMSG_FIRSTHDR(&header); item != nullptr; item = CMSG_NXTHDR(&header, item)) {
    if (item->cmsg_level == SOL_SOCKET && item->cmsg_type == SCM_RIGHTS &&
        item->cmsg_len == CMSG_LEN(2 * sizeof(int))) {
      std::memcpy(&worker.to, CMSG_DATA(item), sizeof(int));
      std::memcpy(&worker.from, CMSG_DATA(item) + sizeof(int), sizeof(int));
    }
  }
  return true;
}

// Runs the one test `name` in this (forked) process and ends it, reporting its verdict.
[[noreturn]] void run_one_test(std::istringstream& words, const std::string& name, int grader, Worker worker) {
  std::string work;
  double cpu_seconds = 0;
  words >> work >> cpu_seconds;
  ::setpgid(0, 0);  // a group of its own: the grader stops the test and what it started at once
  const int nothing = ::open("/dev/null", O_RDONLY);
  ::dup2(nothing, 0);
  ::close(nothing);
  // A backstop only: the grader stops the test at its limit itself.
  const auto seconds = static_cast<rlim_t>(std::ceil(cpu_seconds)) + 1;
  const rlimit cpu{seconds, seconds + 1};
  ::setrlimit(RLIMIT_CPU, &cpu);
  for (std::string variable; words >> variable;) {
    const auto equals = variable.find('=');
    if (equals != std::string::npos) ::setenv(variable.substr(0, equals).c_str(), variable.c_str() + equals + 1, 1);
  }
  if (::chdir(work.c_str()) != 0) std::_Exit(4);
  if (char* here = ::getcwd(nullptr, 0)) {
    ::setenv("HOME", here, 1);
    ::setenv("TMPDIR", here, 1);
    std::free(here);
  }
  ::signal(SIGPIPE, SIG_IGN);  // a worker that has ended is a failed call, not the end of the judge
  if (worker.to >= 0) billiard::testing::use_worker(worker.to, worker.from);
#ifdef GTEST_FLAG_SET
  GTEST_FLAG_SET(filter, name);
#else  // GoogleTest 1.11 (Ubuntu 22.04's) has only the older spelling
  ::testing::GTEST_FLAG(filter) = name;
#endif
  const int status = RUN_ALL_TESTS();
  const auto* unit = ::testing::UnitTest::GetInstance();
  const bool passed = status == 0 && unit->Passed() && unit->test_to_run_count() > 0;
  std::cout.flush();
  std::fflush(nullptr);
  report(grader, passed ? "verdict passed" : "verdict failed");
  std::_Exit(status);  // no destructors or exit handlers: the verdict is said
}

// The test server of --serve=FD (see the top of this file).
int serve(int grader) {
  // Not traceable, nor its memory readable, by processes of the same user (the workers, where
  // they share the grader's user).
  ::prctl(PR_SET_DUMPABLE, 0, 0, 0, 0);
  std::cout.flush();
  std::fflush(nullptr);  // what the program printed so far must not be repeated by each test
  report(grader, "ready");
  std::string line;
  Worker worker;
  while (receive(grader, line, worker)) {
    std::istringstream words(line);
    std::string name;
    if (!(words >> name)) {
      worker.close();
      continue;
    }
    const pid_t pid = ::fork();
    if (pid == 0) run_one_test(words, name, grader, worker);
    worker.close();
    if (pid < 0) {
      report(grader, "ended -1 0");
      continue;
    }
    report(grader, "started " + std::to_string(pid));
    int status = 0;
    rusage usage{};
    while (::wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
    }
    const long long microseconds =
        (static_cast<long long>(usage.ru_utime.tv_sec) + usage.ru_stime.tv_sec) * 1000000LL + usage.ru_utime.tv_usec +
        usage.ru_stime.tv_usec;
    report(grader, "ended " + std::to_string(status) + " " + std::to_string(microseconds));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  billiard::testing::install_picture_listener();
  bool expect_not_implemented = false, list = false;
  int server_reports = -1;
  for (int i = 1; i < argc; ++i) {
    const std::string argument = argv[i];
    if (argument == "--expect-not-implemented") expect_not_implemented = true;
    if (argument == "--list-graded") list = true;
    if (argument.rfind("--serve=", 0) == 0) server_reports = std::atoi(argument.c_str() + 8);
    if (argument == "--brief") {
      auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
      delete listeners.Release(listeners.default_result_printer());
      listeners.Append(new BriefPrinter);  // owned by GoogleTest's listener list
    }
  }
  if (list) return list_graded() ? 0 : 1;
  if (server_reports >= 0) return serve(server_reports);
  if (expect_not_implemented) {
    auto* checker = new StubChecker;  // owned by GoogleTest's listener list
    ::testing::UnitTest::GetInstance()->listeners().Append(checker);
    const int ignored = RUN_ALL_TESTS();  // the checker decides, not the failures it expects
    (void)ignored;
    return checker->report() ? 0 : 1;
  }
  return RUN_ALL_TESTS();
}
