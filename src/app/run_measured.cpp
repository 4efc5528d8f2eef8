// geartopo — the scene and the measurement of the commands on a measurement (run_measured.hpp).
#include "app/run_measured.hpp"

#include "geartopo/files/input_file.hpp"


namespace geartopo::app {

LoadedScene load_scene_for(const MeasuredFlags& opt) {
  LoadedScene s;
  s.file = opt.scene;
  s.wb = std::make_unique<workbench::Workbench>(opt.scene);
  s.text = input::read_input_file(opt.scene, input::kMaxSceneBytes, "scene file");
  return s;
}

commands::ArgumentNames cli_argument_names() { return {"--noise-um", "--candidates"}; }

} // namespace geartopo::app
