// How a call ends, across the judge's boundary: the worker writes what its call threw as an
// Ending and a message; the judge throws the same standard type with the same message again, so
// that the suites' `catch (const std::invalid_argument&)` and the stubs' NotImplemented work as
// they do with the student's code in their own process.
#pragma once

#include "judge/wire.hpp"

#include <exception>

namespace billiard::judge {

// Worker side: writes the exception being handled (call inside a catch block).
void write_current_exception(Writer& reply);

// Judge side: throws what the worker's call threw (its Ending and what follows it in `reply`).
[[noreturn]] void throw_again(Ending ending, Reader& reply);

// Thrown by the judge for an exception that is not a std::exception (the student's code threw
// an int, a string, ...): like the original, not derived from std::exception.
struct NotAStandardException {
  std::string what;
};

// Thrown by the judge for a std::exception of no standard type the suites know.
class OtherException : public std::exception {
 public:
  explicit OtherException(std::string message) : message_(std::move(message)) {}
  const char* what() const noexcept override { return message_.c_str(); }

 private:
  std::string message_;
};

}  // namespace billiard::judge
