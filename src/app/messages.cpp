#include "app/messages.hpp"

#include "geartopo/files/output_folder.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <atomic>
#include <cstdio>
#include <mutex>
#include <utility>
#include <vector>

namespace geartopo::app {

namespace {

std::atomic<bool> quiet_flag{false};

struct HeldMessages {
  std::mutex mutex;
  bool holding = false;
  std::string text;
};

HeldMessages& held_messages() {
  static HeldMessages h;
  return h;
}

} // namespace

void set_quiet(bool q) { quiet_flag = q; }
bool quiet() { return quiet_flag; }

void hold_messages() {
  auto& h = held_messages();
  const std::lock_guard lock(h.mutex);
  h.holding = true;
}

void say(std::string_view line) {
  auto& h = held_messages();
  const std::lock_guard lock(h.mutex);
  if (h.holding) {
    h.text.append(line).append("\n");
    return;
  }
  std::fputs((std::string(line) + "\n").c_str(), stderr);
  std::fflush(stderr);
}

void release_messages() {
  auto& h = held_messages();
  const std::lock_guard lock(h.mutex);
  if (!h.text.empty()) std::fputs(h.text.c_str(), stderr);
  std::fflush(stderr);
  h.text.clear();
  h.holding = false;
}

std::string take_held_messages() {
  auto& h = held_messages();
  const std::lock_guard lock(h.mutex);
  h.holding = false;
  return std::exchange(h.text, {});
}

void finish_output_folder(output::OutputFolder& folder) {
  const auto removed = folder.finish();
  if (quiet()) return;
  for (const auto& t : folder.removed_temporaries())
    say(fmt::format("geartopo: removed {}, left by an interrupted geartopo run", (folder.path() / t).string()));
  if (!removed.empty()) {
    std::vector<std::string> names;
    for (const auto& r : removed) names.push_back(r.generic_string());
    say(fmt::format("geartopo: removed {} file(s) an earlier run wrote into {} and this one did not: {}", removed.size(),
                    folder.path().string(), fmt::join(names, ", ")));
  }
}

void print_notes(const workbench::Workbench& wb) {
  if (quiet()) return;
  for (const auto& n : wb.notes) say("geartopo: note: " + n);
}

} // namespace geartopo::app
