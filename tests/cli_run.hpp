// geartopo tests — run the geartopo program (GEARTOPO_BINARY) as a user does, with its stdout and stderr captured in
// files of `dir`, and return the exit code and both texts. For tests of what a command prints and writes.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>

namespace geartopo::test {

struct CliRun {
  int code = -1;        ///< exit status; -1 when the program did not exit normally
  std::string out, err; ///< what it printed on stdout and stderr
};

/// `geartopo <args>` run by the shell (args are not quoted: test paths have no spaces).
inline CliRun run_geartopo(const std::string& args, const std::filesystem::path& dir) {
  const auto out = dir / "stdout.txt", err = dir / "stderr.txt";
  const int status = std::system((std::string(GEARTOPO_BINARY) + " " + args + " >" + out.string() + " 2>" + err.string()).c_str());
  const auto slurp = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

} // namespace geartopo::test
