// Issue 17: the tutorial's numbers cannot go stale. docs/tutorial.md is run as written: every command of its ```sh
// blocks (build/bin/geartopo → the built program, out/ → a fresh folder), in order; an untagged ``` block right after
// a ```sh block is the expected output of that block's last command. Each expected line must appear in the program's
// output, in order (lines the tutorial leaves out may lie between): exactly, or up to a trailing "…" (the rest of the
// line elided); a line that is only "…" marks such an omission for the reader and is skipped. The truth here is the document a user reads, checked against what the program prints.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct TutorialStep {
  std::vector<std::string> commands; ///< the sh block's commands, comments removed
  std::vector<std::string> expected; ///< the output block after it (empty: none)
  int line = 0;                      ///< line of the sh block in the document
};

std::string trim_right(std::string s) {
  while (!s.empty() && (s.back() == ' ' || s.back() == '\r')) s.pop_back();
  return s;
}

std::vector<TutorialStep> tutorial_steps(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(trim_right(l));
  std::vector<TutorialStep> steps;
  for (size_t i = 0; i < lines.size(); ++i) {
    if (lines[i] != "```sh") continue;
    TutorialStep step;
    step.line = static_cast<int>(i + 1);
    for (++i; i < lines.size() && lines[i] != "```"; ++i) {
      std::string c = lines[i].substr(0, lines[i].find("  #"));
      if (!trim_right(c).empty()) step.commands.push_back(trim_right(c));
    }
    size_t j = i + 1;
    while (j < lines.size() && lines[j].empty()) ++j;
    if (j < lines.size() && lines[j] == "```") {
      for (++j; j < lines.size() && lines[j] != "```"; ++j) step.expected.push_back(lines[j]);
      i = j;
    }
    steps.push_back(step);
  }
  return steps;
}

// Built by appending: GCC 12 warns falsely (-Wstringop-overflow) on std::string::replace inlined here.
std::string replace_all(const std::string& s, const std::string& from, const std::string& to) {
  std::string out;
  size_t start = 0;
  for (size_t at = s.find(from); at != std::string::npos; at = s.find(from, start)) {
    out.append(s, start, at - start);
    out += to;
    start = at + from.size();
  }
  out.append(s, start, std::string::npos);
  return out;
}

std::string run_captured(const std::string& command, int& code) {
  const fs::path out = fs::temp_directory_path() / ("geartopo_tutorial_out_" + std::to_string(::getpid()));
  const int status = std::system((command + " --quiet >" + out.string() + " 2>&1").c_str());
  code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(out);
  std::stringstream s;
  s << in.rdbuf();
  fs::remove(out);
  return s.str();
}

// Empty when every expected line is found in order; else the first one that is not.
std::string first_missing(const std::vector<std::string>& expected, const std::string& output) {
  std::vector<std::string> got;
  std::istringstream in(output);
  for (std::string l; std::getline(in, l);) got.push_back(trim_right(l));
  size_t at = 0;
  for (const auto& e : expected) {
    const std::string t = trim_right(e);
    if (t.find_first_not_of(' ') != std::string::npos && t.substr(t.find_first_not_of(' ')) == "…") continue;
    const bool prefix = t.size() >= 3 && t.compare(t.size() - 3, 3, "…") == 0;
    const std::string want = prefix ? trim_right(t.substr(0, t.size() - 3)) : t;
    bool found = false;
    for (size_t k = at; k < got.size(); ++k) {
      const bool match = prefix ? got[k].compare(0, want.size(), want) == 0 : got[k] == want;
      if (match) {
        at = k + 1;
        found = true;
        break;
      }
    }
    if (!found) return t;
  }
  return {};
}

} // namespace

TEST(Tutorial, EveryCommandRunsAndPrintsWhatTheTutorialShows) {
  const fs::path source(GEARTOPO_SOURCE_DIR);
  const auto steps = tutorial_steps(source / "docs" / "tutorial.md");
  ASSERT_GE(steps.size(), 4u) << "docs/tutorial.md lost its ```sh blocks";
  const fs::path out = fs::temp_directory_path() / ("geartopo_tutorial_" + std::to_string(::getpid()));
  fs::remove_all(out);
  fs::create_directories(out);
  // Built by appending: GCC 12 warns falsely on `"literal" + std::string&&` (as in src/files/atomic_write.cpp).
  std::string out_prefix = " ";
  out_prefix += out.string();
  out_prefix += '/';
  std::string cd = "cd ";
  cd += source.string();
  cd += " && ";
  int checked = 0;
  for (const auto& step : steps) {
    std::string output;
    for (const auto& c : step.commands) {
      std::string cmd = replace_all(c, "build/bin/geartopo", GEARTOPO_BINARY);
      cmd = replace_all(cmd, " out/", out_prefix);
      int code = 0;
      output = run_captured(cd + cmd, code);
      ASSERT_EQ(code, 0) << "docs/tutorial.md:" << step.line << ": " << c << "\n" << output;
    }
    if (step.expected.empty()) continue;
    ++checked;
    const std::string missing = first_missing(step.expected, output);
    EXPECT_TRUE(missing.empty()) << "docs/tutorial.md:" << step.line << ": the program no longer prints\n  " << missing
                                 << "\nit prints:\n" << output;
  }
  EXPECT_GE(checked, 3) << "the tutorial shows fewer outputs than it used to";
  fs::remove_all(out);
}
