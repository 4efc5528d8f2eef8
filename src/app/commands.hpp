// geartopo — the subcommands of the geartopo CLI. Each registers its flags on the CLI11 app (<command>_command.cpp)
// and sets the action that runs after parsing: its body, a named function of its own (run_<command>.cpp, declared
// with the command's options in <command>_command.hpp). Exit codes: 0 success, 1 bad input (clear message on
// stderr), 2 bad usage.
#pragma once

#include <functional>

namespace CLI {
class App;
}
namespace geartopo::workbench {
struct Workbench;
}

namespace geartopo::app {

using Action = std::function<int()>;

/// The scene's Workbench (workbench/workbench.hpp), by its short name in every command.
using workbench::Workbench;

/// `geartopo gear SCENE [--json] [--mesh FILE]`
void register_gear_command(CLI::App& app, Action& action);
/// `geartopo machine SCENE --pose X,Y,Z,A_deg,C_deg [--json]`
void register_machine_command(CLI::App& app, Action& action);
/// `geartopo simulate SCENE --out DIR [--method exact|linear] [--teeth 1,18|all] [--dense NxM]`
void register_simulate_command(CLI::App& app, Action& action);
/// `geartopo evaluate SCENE --out DIR [--method exact|linear] [--traces FILE] [--prediction FILE]`
void register_evaluate_command(CLI::App& app, Action& action);
/// `geartopo compensate SCENE --out DIR [--method paper|flank] [--step MM]`
void register_compensate_command(CLI::App& app, Action& action);
/// `geartopo synth TRUTH_SCENE --out FILE [--teeth 1,18] [--noise-um S] [--seed N] [--stroke-scatter] [--corrections F]`
void register_synth_command(CLI::App& app, Action& action);
/// `geartopo diagnose SCENE --measured FILE --out DIR [--noise-um S] [--candidates a,b]`
void register_diagnose_command(CLI::App& app, Action& action);
/// `geartopo plan SCENE --measured FILE [--out DIR] [--noise-um S]` — what to measure next when ambiguous
void register_plan_command(CLI::App& app, Action& action);
/// `geartopo compare SCENE --measured FILE --out DIR [--noise-um S]`
void register_compare_command(CLI::App& app, Action& action);
/// `geartopo report SCENE [--measured FILE] --out DIR`
void register_report_command(CLI::App& app, Action& action);
/// `geartopo merge PARTS... --out DIR` — Monte Carlo shards into one prediction (docs/monte-carlo.md)
void register_merge_command(CLI::App& app, Action& action);
/// `geartopo run SCENE --out DIR` — the main job
void register_run_command(CLI::App& app, Action& action);

} // namespace geartopo::app
