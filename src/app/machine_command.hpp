// geartopo machine SCENE --pose X,Y,Z,A_deg,C_deg [--json]: the wheel's pose at one axis pose, ideal (Eq. 11) and
// with the scene's errors (exact and first order), and the Jacobian J_M.
#pragma once

#include <string>
#include <vector>

namespace geartopo::app {

struct MachineOptions {
  std::string scene;
  std::vector<double> pose; ///< X, Y, Z mm, A, C deg
  bool json = false;
};

/// The command's work once its flags are parsed (machine_command.cpp); returns the exit code.
int run_machine(const MachineOptions& opt);

} // namespace geartopo::app
