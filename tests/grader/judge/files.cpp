#include "judge/files.hpp"

#include <fstream>
#include <iterator>
#include <system_error>

namespace billiard::judge {

namespace fs = std::filesystem;

namespace {

std::string read_capped(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string content;
  content.resize(kMaxFileBytes);
  in.read(content.data(), static_cast<std::streamsize>(content.size()));
  content.resize(static_cast<std::size_t>(in.gcount()));
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
