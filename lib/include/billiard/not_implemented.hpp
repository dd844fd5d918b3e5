// The error a stub in tasks/ throws until the student writes the task. Deliberately not a
// std::invalid_argument: a stub must fail every graded test, including the ones that expect
// invalid arguments to be refused.
#pragma once

#include <stdexcept>
#include <string>

namespace billiard {

class NotImplemented : public std::logic_error {
 public:
  // task_number: the task's number in the course's catalogue (tests/grader/course.txt);
  // function: e.g. "propagate"; file: e.g. "tasks/propagate.cpp".
  NotImplemented(int task_number, const std::string& function, const std::string& file);
  int task_number() const { return task_number_; }
  const std::string& function() const { return function_; }
  const std::string& file() const { return file_; }

 private:
  int task_number_;
  std::string function_, file_;
};

}  // namespace billiard
