// geartopo diagnosis — the golden set's dump (diagnosis_dump.hpp).
#include "diagnosis_dump.hpp"

#include "geartopo/diagnosis/diagnosis_json.hpp"

#include <fmt/format.h>

#include <atomic>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>
#include <string>
#include <unistd.h>

namespace geartopo::diagnosis {
namespace {

/// A process' arguments (/proc/PID/cmdline, NUL-separated), as one string with spaces.
std::string command_line(const std::string& pid) {
  std::ifstream in("/proc/" + pid + "/cmdline", std::ios::binary);
  std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (char& c : s)
    if (c == '\0') c = ' ';
  return s;
}

std::string gtest_filter(const std::string& cmdline) {
  std::smatch m;
  static const std::regex filter("--gtest_filter=(\\S+)");
  return std::regex_search(cmdline, m, filter) ? m[1].str() : std::string();
}

/// The name a dump gets: the test, a hash of this program's arguments with temporary folders blanked (the CLI tests'
/// mkdtemp names differ from run to run), and this process' count of diagnoses.
std::string dump_name() {
  static std::atomic<int> count{0};
  const std::string own = command_line("self");
  std::string test;
  if (const char* py = std::getenv("PYTEST_CURRENT_TEST")) test = py;
  if (test.empty()) test = gtest_filter(own);
  if (test.empty()) test = gtest_filter(command_line(std::to_string(getppid())));
  if (test.empty()) test = "untested";
  static const std::regex temporary("/tmp/[^ ]*");
  const std::string args = std::regex_replace(own, temporary, "/tmp/*");
  std::string name = fmt::format("{}.{:016x}.{}", test, std::hash<std::string>{}(args), count++);
  for (char& c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-')) c = '_';
  return name;
}

} // namespace

void dump_if_asked(const Diagnosis& d) {
  const char* folder = std::getenv("GEARTOPO_DIAGNOSIS_DUMP");
  if (!folder || !*folder) return;
  std::filesystem::create_directories(folder);
  std::ofstream(std::filesystem::path(folder) / (dump_name() + ".json")) << diagnosis_json("", "", d, 0.0).dump(1) << "\n";
}

} // namespace geartopo::diagnosis
