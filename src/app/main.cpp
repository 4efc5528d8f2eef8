// geartopo — command-line entry. Exit codes: 0 success, 1 bad input, 2 bad usage.
#include "app/commands.hpp"
#include "geartopo/commands/limits.hpp"
#include "app/messages.hpp"
#include "geartopo/files/termination.hpp"

#include <CLI/CLI.hpp>

#include <iostream>
#include <string>

namespace {

/// 2 with a usage message naming the commands when the first word that is not an option is not a command; 0 otherwise
/// (no word, or a command: CLI11 parses the rest).
int refuse_unknown_command(CLI::App& app, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.empty() || word[0] == '-') continue;
    std::string names;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
      if (sub->check_name(word)) return 0;
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    std::cerr << "geartopo: usage: '" << word << "' is not a command (one of " << names << "; geartopo --help)\n";
    return 2;
  }
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"geartopo — tooth-flank topology of profile-ground helical gears (units: mm, µm, deg)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "geartopo 0.1.0");
  // --quiet belongs to the program but is accepted after any subcommand (`geartopo run SCENE --out D --quiet`):
  // subcommands created after fallthrough() pass options they do not know up to the program.
  app.fallthrough();
  bool quiet = false;
  app.add_flag("--quiet,-q", quiet, "No progress, work estimates or notes on stderr (warnings and errors stay)");
  // An interrupted run (Ctrl-C, kill, a closed terminal) leaves no temporary output file behind (files/termination.hpp).
  geartopo::output::remove_temporaries_on_termination_signals();
  geartopo::app::Action action;
  geartopo::app::register_run_command(app, action);
  geartopo::app::register_gear_command(app, action);
  geartopo::app::register_machine_command(app, action);
  geartopo::app::register_simulate_command(app, action);
  geartopo::app::register_evaluate_command(app, action);
  geartopo::app::register_compensate_command(app, action);
  geartopo::app::register_synth_command(app, action);
  geartopo::app::register_compare_command(app, action);
  geartopo::app::register_diagnose_command(app, action);
  geartopo::app::register_plan_command(app, action);
  geartopo::app::register_report_command(app, action);
  geartopo::app::register_merge_command(app, action);
  geartopo::app::register_series_command(app, action);

  // An unknown command is an error whatever follows it: CLI11 answers `geartopo series --help` with the program's help
  // and exit 0 (the help flag is handled before the unknown word), so the first word is checked first.
  if (const int code = refuse_unknown_command(app, argc, argv); code != 0) return code;
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e); // prints the message and the usage hint
    return 2;
  }
  geartopo::app::set_quiet(quiet);
  // Errors first: the command's banner, notes and warnings are held until it ends (or starts long work), so that the
  // first line a user or a script sees of a command that fails is its error.
  geartopo::app::hold_messages();
  int code = 0;
  std::string error;
  try {
    code = action ? action() : 2;
  } catch (const CLI::ValidationError& e) {
    code = 2;
    error = std::string("geartopo: usage: ") + e.what();
  } catch (const geartopo::commands::ArgumentError& e) { // a flag's value the command refuses: bad usage, named
    code = 2;
    error = std::string("geartopo: usage: ") + e.what();
  } catch (const std::exception& e) {
    code = 1;
    error = std::string("geartopo: error: ") + e.what();
  }
  if (error.empty()) {
    geartopo::app::release_messages();
    return code;
  }
  std::cerr << error << "\n" << geartopo::app::take_held_messages() << std::flush;
  return code;
}
