// geartopo — a twist of the chain's workpiece frame referred to the gear's datum frame (datum_shift.hpp). Units: mm, rad.
#include "geartopo/machine/datum_shift.hpp"

#include <Eigen/Geometry>

namespace geartopo::machine {

Vector6d twist_at_datum(const Vector6d& xi_w, double datum_face_z_mm) {
  Vector6d xi = xi_w;
  xi.head<3>() += Eigen::Vector3d(0.0, 0.0, -datum_face_z_mm).cross(Eigen::Vector3d(xi_w.tail<3>()));
  return xi;
}

} // namespace geartopo::machine
