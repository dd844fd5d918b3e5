// The judge's side of the course's functions: linked into a graded suite instead of the course's
// code, each function sends its call to the running test's worker (worker_main.cpp), waits for
// the answer and returns it, or throws what the student's code threw, as if the call had been
// made here. The suite's assertions, its verdict and everything it trusts stay in this process,
// where no submitted code runs; the worker's answers are data to judge, nothing more.
//
// When the worker ends during a call (a crash, exit(), a limit) or answers with a malformed
// message, the test fails with a message that says so, and every later call of the test fails at
// once: the call throws WorkerGone, which is no std::exception, so that no `catch` in a suite
// takes it for an error the student's code reported.
#include "judge/endings.hpp"
#include "judge/files.hpp"
#include "judge/wire.hpp"
#include "support/student_code.hpp"
#include "support/student_messages.hpp"

#include <gtest/gtest.h>

#include <string>
#include <tuple>
#include <type_traits>

namespace billiard {

namespace judge {
namespace {

int to_worker = -1, from_worker = -1;
bool gone = false;

struct WorkerGone {};

// Fails the test once, for the first call that could not be made.
[[noreturn]] void worker_gone(const std::string& call, const std::string& what) {
  gone = true;
  ADD_FAILURE() << testing::explain(
      call + " to return or to throw an exception", "the process running your code ended during the call" + what,
      "what ends a program: exit() or abort(), a failed assert, an uncaught exception in a thread, reading or "
      "writing outside an array (a segmentation fault), an endless recursion, or running out of memory or time "
      "(the first line of this message says which, where the grader can tell)");
  throw WorkerGone{};
}

// Sends a call and receives the worker's answer.
Reader call_worker(const Writer& request, const std::string& call) {
  if (to_worker < 0) throw std::logic_error("the grader's judge has no worker to call " + call);
  if (gone) throw WorkerGone{};
  try {
    send(to_worker, request.bytes());
    return Reader(receive(from_worker));
  } catch (const ProtocolError&) {
    worker_gone(call, "");
  }
}

// The end of an answer: returns if the call returned, else throws what it threw. A malformed
// answer ends the worker's use, as if it had ended.
void finish(Reader& reply, const std::string& call) {
  try {
    const auto ending = reply.get<Ending>();
    if (ending != Ending::returned) throw_again(ending, reply);
  } catch (const ProtocolError& error) {
    worker_gone(
        call, std::string(", or wrote something else than its answer to the grader's channel (") + error.what() + ")");
  }
}

// Reads the result of a call that returned, after finish().
template <typename T>
T result(Reader& reply, const std::string& call) {
  try {
    T value{};
    reply >> value;
    reply.expect_end();
    return value;
  } catch (const ProtocolError& error) {
    worker_gone(
        call, std::string(", or wrote something else than its answer to the grader's channel (") + error.what() + ")");
  }
}

// Reads the arguments a call may change, which come first in every answer.
template <typename... T>
void read_back(Reader& reply, const std::string& call, T&... arguments) {
  try {
    (reply >> ... >> arguments);
  } catch (const ProtocolError& error) {
    worker_gone(
        call, std::string(", or wrote something else than its answer to the grader's channel (") + error.what() + ")");
  }
}

void expect_end(Reader& reply, const std::string& call) {
  try {
    reply.expect_end();
  } catch (const ProtocolError& error) {
    worker_gone(
        call, std::string(", or wrote something else than its answer to the grader's channel (") + error.what() + ")");
  }
}

// A course function's call, made in the worker: `Function` is the function (a proxy itself), whose
// declared parameters say what crosses which way (wire.hpp).
template <auto Function>
struct Forward;
template <typename Result, typename... Parameter, Result (*Function)(Parameter...)>
struct Forward<Function> {
  template <typename... Argument>
  static Result call(Call which, const std::string& name, std::tuple<Argument&...> arguments) {
    Writer request;
    request << which;
    std::apply([&](auto&... argument) { (send<Parameter>(request, argument), ...); }, arguments);
    auto reply = call_worker(request, name);
    std::apply([&](auto&... argument) { (take_back<Parameter>(reply, name, argument), ...); }, arguments);
    finish(reply, name);
    if constexpr (std::is_void_v<Result>) {
      expect_end(reply, name);
    } else {
      return result<Result>(reply, name);
    }
  }

  template <typename P, typename A>
  static void send(Writer& request, const A& argument) {
    if constexpr (is_path<P>) {
      request << describe_file(argument);
    } else {
      request << static_cast<const std::decay_t<P>&>(argument);
    }
  }

  template <typename P, typename A>
  static void take_back(Reader& reply, const std::string& name, A& argument) {
    if constexpr (is_path<P>) {
      FileState file;
      read_back(reply, name, file);
      copy_back(argument, file);
    } else if constexpr (comes_back<P>) {
      read_back(reply, name, argument);
    }
  }
};

}  // namespace
}  // namespace judge

namespace testing {

void use_worker(int to_worker, int from_worker) {
  judge::to_worker = to_worker;
  judge::from_worker = from_worker;
  judge::gone = false;
}

}  // namespace testing

using judge::Call;
using judge::Writer;

// The course's functions (calls.hpp), each a call of the worker.
#define BILLIARD_PROXY(type, name, parameters, arguments) \
  type name parameters { return judge::Forward<&name>::call(Call::name, #name, std::forward_as_tuple arguments); }
BILLIARD_COURSE_CALLS(BILLIARD_PROXY)
#undef BILLIARD_PROXY

namespace testing {

cli::Run run_student_program(const std::vector<std::string>& arguments,
                             const std::vector<std::pair<std::string, std::string>>& inputs,
                             const cli::Limits& limits) {
  const std::string call = "your program";
  judge::ProgramRun run{arguments, inputs, limits.seconds};
  Writer request;
  request << Call::run_program << run;
  auto reply = judge::call_worker(request, call);
  judge::finish(reply, call);
  const auto result = judge::result<judge::ProgramResult>(reply, call);
  cli::Run done;
  done.status = result.status;
  done.signal = result.signal;
  done.timed_out = result.timed_out;
  done.seconds = result.seconds;
  done.out = result.out;
  done.err = result.err;
  return done;
}

}  // namespace testing
}  // namespace billiard
