// geartopo-mpi — `mpirun -n N geartopo-mpi compensate SCENE --out DIR --samples M --seed S`: compensate with its
// Monte Carlo samples scattered over the MPI ranks (mpi_driver.hpp, docs/monte-carlo.md "MPI"). Every rank parses the
// same command line and builds the same scene; rank 0 alone prints and writes, exactly the files of one
// `geartopo compensate` run. Exit codes as geartopo's (0, 1 bad input, 2 bad usage), the same on every rank.
#include "app/commands.hpp"
#include "app/mpi_driver.hpp"
#include "app/messages.hpp"
#include "geartopo/files/termination.hpp"

#include <CLI/CLI.hpp>

#include <iostream>
#include <string>

namespace {

using geartopo::app::MpiMonteCarloDriver;

/// The message of a failure on this rank, printed by the lowest failing rank only (the others failed the same way
/// on the same input, or succeeded).
void report_rank_failure(const MpiMonteCarloDriver& driver, int failing_rank, const std::string& message) {
  // Errors first (as geartopo's main): what the command had said on this rank follows its error.
  const std::string held = geartopo::app::take_held_messages();
  if (failing_rank != driver.rank() || message.empty()) {
    std::cerr << held << std::flush;
    return;
  }
  std::cerr << (driver.rank() == 0 ? std::string() : "geartopo-mpi: rank " + std::to_string(driver.rank()) + " of " +
                                                         std::to_string(driver.size()) + ": ")
            << message << "\n"
            << held << std::flush;
}

int run_on_this_rank(MpiMonteCarloDriver& driver, int argc, char** argv) {
  CLI::App app{"geartopo-mpi — geartopo compensate with the Monte Carlo samples scattered over MPI ranks: "
               "mpirun -n N geartopo-mpi compensate SCENE --out DIR --samples M --seed S (units: mm, µm, deg)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "geartopo-mpi 0.1.0");
  app.fallthrough();
  bool quiet = false;
  app.add_flag("--quiet,-q", quiet, "No progress, work estimates or notes on stderr (warnings and errors stay)");
  geartopo::output::remove_temporaries_on_termination_signals();
  geartopo::app::Action action;
  geartopo::app::register_compensate_command(app, action);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Usually every rank parsed the same words: help, version or the usage error is printed once, by rank 0 (by the
    // lowest failing rank when the ranks were given different words: mpirun's MPMD form `-n 1 … : -n 1 …`).
    const auto agreed = driver.settle(e.get_exit_code() == 0 ? 0 : 2);
    if (driver.rank() == (agreed.failing_rank >= 0 ? agreed.failing_rank : 0)) {
      if (driver.rank() != 0) std::cerr << "geartopo-mpi: rank " << driver.rank() << " of " << driver.size() << ":\n";
      app.exit(e);
    }
    return agreed.exit_code;
  }
  geartopo::app::set_quiet(quiet || driver.rank() != 0); // notes and progress from rank 0 only

  geartopo::app::hold_messages();
  int code = 2;
  std::string message;
  try {
    code = action ? action() : 2;
  } catch (const geartopo::app::OtherRankFailed& e) {
    return e.exit_code; // the failing rank says why
  } catch (const CLI::ValidationError& e) {
    code = 2;
    message = std::string("geartopo: usage: ") + e.what();
  } catch (const std::exception& e) {
    code = 1;
    message = std::string("geartopo: error: ") + e.what();
  }
  if (const auto& agreed = driver.agreed_failure()) { // the ranks agreed on a failure inside an adaptive run
    report_rank_failure(driver, agreed->failing_rank, message);
    return agreed->exit_code;
  }
  if (driver.settled()) { // past the gather: rank 0 writing the files, its failure its own
    report_rank_failure(driver, driver.rank(), message);
    return code;
  }
  const auto agreed = driver.settle(code);
  report_rank_failure(driver, agreed.failing_rank, message);
  return agreed.exit_code;
}

} // namespace

int main(int argc, char** argv) {
  // Only the main thread calls MPI; parallel_for's workers compute samples in between (MPI_THREAD_FUNNELED).
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  int code = 0;
  {
    MpiMonteCarloDriver driver(MPI_COMM_WORLD);
    geartopo::app::set_monte_carlo_driver(&driver);
    code = run_on_this_rank(driver, argc, argv);
    geartopo::app::set_monte_carlo_driver(nullptr);
  }
  MPI_Finalize();
  return code;
}
