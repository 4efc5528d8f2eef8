// geartopo gear SCENE [--json] [--mesh FILE]: the gear's geometry (ISO 21771), optionally its mesh.
#pragma once

#include <string>

namespace geartopo::app {

struct GearOptions {
  std::string scene, mesh;
  bool json = false;
};

/// The command's work once its flags are parsed (gear_command.cpp); returns the exit code.
int run_gear(const GearOptions& opt);

} // namespace geartopo::app
