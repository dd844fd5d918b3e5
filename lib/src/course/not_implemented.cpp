#include "billiard/not_implemented.hpp"

#include <filesystem>

namespace billiard {

NotImplemented::NotImplemented(int task_number, const std::string& function, const std::string& file)
    : std::logic_error("task " + std::to_string(task_number) + " (" + function +
                       ") is not implemented yet: write it in " + file +
                       ", then run its tests with: ./build.sh test -L " +
                       std::filesystem::path(file).stem().string()),
      task_number_(task_number),
      function_(function),
      file_(file) {}

}  // namespace billiard
