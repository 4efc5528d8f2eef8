// geartopo Python module — a scene as Python holds it: the Workbench (everything the scene describes, built and
// checked once) with the scene's text and where it came from, which the diagnosis needs to write the scene with an
// effect added. Immutable; shared by every call that takes it.
#pragma once

#include "geartopo/workbench/workbench.hpp"

#include <filesystem>
#include <memory>
#include <string>

namespace geartopo::python {

struct PyScene {
  std::shared_ptr<const workbench::Workbench> wb;
  std::string source;          ///< the file, or the name given to a YAML text (messages say it)
  std::string text;            ///< the YAML text
  std::filesystem::path dir;   ///< the folder its relative paths (machine.tables, measurement.measured) start from
};

} // namespace geartopo::python
