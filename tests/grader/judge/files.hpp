// A file argument across the judge's boundary (wire.hpp, FileState): the judge describes the
// path it passes (the file's name, whether its folder exists or is a file, what the file holds),
// the worker makes the same in a folder of its own and calls with that path, and the file as
// the call left it comes back and is written where the judge's test looks for it.
#pragma once

#include "judge/wire.hpp"

#include <filesystem>

namespace billiard::judge {

// The most of a file that crosses (a table's picture has a few kilobytes, a movie's some hundreds).
inline constexpr std::size_t kMaxFileBytes = 64u << 20;

// The state of `path` and of its folder.
FileState describe_file(const std::filesystem::path& path);

// Worker side: makes `state` in a new folder under `work` and returns the path to call with.
std::filesystem::path make_file(const FileState& state, const std::filesystem::path& work);

// Judge side: makes `path` what the worker's file became (written, or removed).
void copy_back(const std::filesystem::path& path, const FileState& state);

}  // namespace billiard::judge
