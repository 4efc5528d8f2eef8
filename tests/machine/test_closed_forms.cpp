// geartopo tests — the closed forms printed in docs/machine-model.md (generated symbolically by
// derive_closed_forms.py into closed_forms_generated.inc) equal the library's adjoint-transport results.
// Units: mm, rad.
#include "test_helpers.hpp"

#include "geartopo/machine/first_order.hpp"
#include "geartopo/machine/jacobian.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace geartopo::machine {
namespace {

TEST(ClosedForms, DocumentedColumnsEqualTheLibrary) {
  std::mt19937 rng(51);
  MachineData data;
  for (int trial = 0; trial < 100; ++trial) {
    const AxisPose q = test::random_pose(rng);
    const double x = q.x, y = q.y, z = q.z;
    const double sa = std::sin(q.a), ca = std::cos(q.a), sg = std::sin(q.c), cg = std::cos(q.c);
    Matrix6E Jw_e;
    Matrix65 Jw_q, Jg_q;
#include "closed_forms_generated.inc"
    error_jacobians(q, data);
    EXPECT_LT((data.J_twistw_e - Jw_e).cwiseAbs().maxCoeff(), 1e-12 * 2000.0);
    EXPECT_LT((J_twistw_q(q) - Jw_q).cwiseAbs().maxCoeff(), 1e-12 * 2000.0);
    EXPECT_LT((J_twistg_q(q) - Jg_q).cwiseAbs().maxCoeff(), 1e-12 * 2000.0);
  }
}

} // namespace
} // namespace geartopo::machine
