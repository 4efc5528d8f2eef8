// The inputs of this run (input_registry.hpp): device and inode of each, with the name it was given.
#include "geartopo/files/input_registry.hpp"

#include "geartopo/files/output_error.hpp"

#include <mutex>
#include <string>
#include <sys/stat.h>
#include <vector>

namespace geartopo::output {

namespace fs = std::filesystem;

namespace {

struct InputFile {
  dev_t dev;
  ino_t ino;
  std::string name;
};
std::mutex inputs_mutex;
std::vector<InputFile>& input_files() {
  static std::vector<InputFile> list;
  return list;
}

// Under inputs_mutex.
const InputFile* find_input(const fs::path& file) {
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) return nullptr;
  for (const auto& i : input_files()) {
    if (i.dev != st.st_dev || i.ino != st.st_ino) continue;
    // Still the input under its name? An input removed since it was read may have left its inode to a new file.
    struct stat now {};
    if (::stat(i.name.c_str(), &now) == 0 && now.st_dev == i.dev && now.st_ino == i.ino) return &i;
  }
  return nullptr;
}

} // namespace

void note_input(const fs::path& file) {
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) return;
  const std::lock_guard lock(inputs_mutex);
  for (auto& i : input_files())
    if (i.dev == st.st_dev && i.ino == st.st_ino) {
      i.name = file.string(); // the same file under another name, or a removed input's inode reused
      return;
    }
  input_files().push_back({st.st_dev, st.st_ino, file.string()});
}

bool is_an_input(const fs::path& file) {
  const std::lock_guard lock(inputs_mutex);
  return find_input(file) != nullptr;
}

void check_not_an_input(const fs::path& output) {
  const std::lock_guard lock(inputs_mutex);
  if (const InputFile* i = find_input(output))
    throw OutputError(output, "it is " + i->name + ", an input of this run: geartopo never replaces what it reads; "
                                "choose another output name or folder");
}

} // namespace geartopo::output
