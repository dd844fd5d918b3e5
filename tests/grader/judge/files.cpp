#include "judge/files.hpp"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <system_error>

namespace billiard::judge {

namespace fs = std::filesystem;

namespace {

// The file's first kMaxFileBytes, read in steps (its size as the folder says may be wrong, for
// a file that another process is still writing).
std::string read_capped(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string content;
  char block[65536];
  while (content.size() < kMaxFileBytes && in.read(block, sizeof block).gcount() > 0) {
    content.append(block, static_cast<std::size_t>(std::min<std::streamsize>(
                              in.gcount(), static_cast<std::streamsize>(kMaxFileBytes - content.size()))));
  }
  return content;
}

// A plain name for the file in the worker's folder: the judge's own name where it is one.
std::string plain_name(const fs::path& path) {
  const std::string name = path.filename().string();
  return name.empty() || name == "." || name == ".." ? std::string("file") : name;
}

}  // namespace

FileState describe_file(const fs::path& path) {
  FileState state;
  state.name = plain_name(path);
  std::error_code error;
  const fs::path folder = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  const auto folder_status = fs::status(folder, error);
  state.parent = fs::is_directory(folder_status) ? FileState::Parent::folder
                 : fs::exists(folder_status)     ? FileState::Parent::file
                                                 : FileState::Parent::missing;
  const auto file_status = fs::status(path, error);
  if (fs::is_regular_file(file_status)) {
    state.kind = FileState::Kind::regular;
    state.content = read_capped(path);
  } else {
    state.kind = fs::exists(file_status) ? FileState::Kind::other : FileState::Kind::absent;
  }
  return state;
}

fs::path make_file(const FileState& state, const fs::path& work) {
  static int made = 0;
  const fs::path folder = work / ("files-" + std::to_string(++made));
  fs::create_directories(folder);
  const fs::path parent = folder / (state.parent == FileState::Parent::missing ? "missing" : "folder");
  const fs::path path = parent / plain_name(state.name);
  if (state.parent == FileState::Parent::file) {
    std::ofstream(parent, std::ios::binary) << "";
  } else if (state.parent == FileState::Parent::folder) {
    fs::create_directory(parent);
    if (state.kind == FileState::Kind::regular) {
      std::ofstream(path, std::ios::binary) << state.content;
    } else if (state.kind == FileState::Kind::other) {
      fs::create_directory(path);
    }
  }
  return path;
}

void copy_back(const fs::path& path, const FileState& state) {
  std::error_code error;
  if (state.kind == FileState::Kind::regular) {
    if (!path.parent_path().empty()) fs::create_directories(path.parent_path(), error);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << state.content;
  } else if (state.kind == FileState::Kind::absent && fs::is_regular_file(fs::symlink_status(path, error))) {
    fs::remove(path, error);
  }
}

}  // namespace billiard::judge
