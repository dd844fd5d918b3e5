// The worker: the process in which the student's code runs under the grader, linked with the
// student's task file and the code of the other tasks (the reference's, as compiled objects, or
// the student's own). It answers the judge's calls (proxy.cpp) one at a time, on descriptors 3
// (in) and 4 (out), until the judge closes them: reads a call, makes it, and sends back the
// arguments the call may change and what it returned or threw. Whatever else the student's code does here (print,
// exit, crash, write to the channel itself) costs only this test's answers.
//
// It runs in a cell (tests/grader/cell/cell.c): its own folder, which holds the files of the
// calls that take a path, and nothing of the grader's or of other tests.
#include "judge/endings.hpp"
#include "judge/files.hpp"
#include "judge/wire.hpp"

#include "billiard/extensions.hpp"

#include <sys/prctl.h>

#include <cstdio>
#include <iostream>
#include <tuple>
#include <type_traits>

namespace {

using namespace billiard;
using judge::Call;
using judge::comes_back;
using judge::Ending;
using judge::is_path;
using judge::Reader;
using judge::Writer;

// The pipes from and to the judge.
constexpr int kFromJudge = 3, kToJudge = 4;

// Makes `call`, then writes what `changed` writes (the arguments the call may change, whether it
// returned or threw) and how the call ended: Ending::returned and its value, or what it threw.
template <typename Function, typename Changed>
void answer(Writer& reply, Function&& call, Changed&& changed) {
  Writer ending;
  try {
    if constexpr (std::is_void_v<decltype(call())>) {
      call();
      ending << Ending::returned;
    } else {
      const auto value = call();
      ending << Ending::returned << value;
    }
  } catch (...) {
    judge::write_current_exception(ending);
  }
  changed(reply);
  reply.append(ending);
}

// Answers a call of a course function: reads its arguments as the function declares its
// parameters (a file's path arrives as the file, made in this worker's folder), makes the call,
// and sends back what may have changed (wire.hpp) and how it ended.
template <auto Function>
struct Serve;
template <typename Result, typename... Parameter, Result (*Function)(Parameter...)>
struct Serve<Function> {
  static void call(Reader& request, Writer& reply) {
    std::tuple<std::decay_t<Parameter>...> values{take<Parameter>(request)...};  // in order: braces
    answer(
        reply, [&] { return std::apply([](auto&... value) { return Function(value...); }, values); },
        [&](Writer& out) { std::apply([&](auto&... value) { (send_back<Parameter>(out, value), ...); }, values); });
  }

  template <typename P>
  static std::decay_t<P> take(Reader& request) {
    if constexpr (is_path<P>) {
      return judge::make_file(request.get<judge::FileState>(), {});
    } else {
      return request.get<std::decay_t<P>>();
    }
  }

  template <typename P, typename V>
  static void send_back(Writer& out, const V& value) {
    if constexpr (is_path<P>) {
      out << judge::describe_file(value);
    } else if constexpr (comes_back<P>) {
      out << value;
    }
  }
};

// Answers one call.
void serve(Reader& request, Writer& reply) {
  switch (request.get<Call>()) {
#define BILLIARD_SERVE(type, name, parameters, arguments) \
  case Call::name:                                        \
    Serve<&billiard::name>::call(request, reply);         \
    return;
    BILLIARD_COURSE_CALLS(BILLIARD_SERVE)
#undef BILLIARD_SERVE
    case Call::run_program:
      break;
  }
  answer(reply, []() -> int { throw std::logic_error("this worker runs course functions, not programs"); },
         [](Writer&) {});
}

}  // namespace

int main() {
  // Not traceable by processes of the same user (where cells share one): the cell's filter keeps it so.
  ::prctl(PR_SET_DUMPABLE, 0, 0, 0, 0);
  for (;;) {
    std::string message;
    try {
      message = judge::receive(kFromJudge);
    } catch (const judge::ProtocolError&) {
      return 0;  // the judge is done with this test
    }
    Reader request(std::move(message));
    Writer reply;
    serve(request, reply);
    std::cout.flush();
    std::fflush(nullptr);  // what the code printed reaches the grader before the answer's end
    judge::send(kToJudge, reply.bytes());
  }
}
