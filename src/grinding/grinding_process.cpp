#include "grinding/grinding_process.hpp"

#include "machine/chain.hpp"

namespace geartopo::grinding {

machine::Pose IdealProcess::actual_wMg(const PathPoint& pp) const { return machine::ideal_wMg(pp.q); }

} // namespace geartopo::grinding
