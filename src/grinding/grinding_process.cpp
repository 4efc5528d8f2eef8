#include "geartopo/grinding/grinding_process.hpp"

#include "geartopo/machine/chain.hpp"

namespace geartopo::grinding {

machine::Pose IdealProcess::actual_wMg(const PathPoint& pp) const { return machine::ideal_wMg(pp.q); }

} // namespace geartopo::grinding
