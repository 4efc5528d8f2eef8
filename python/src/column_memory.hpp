// geartopo Python module — the memory of result columns, kept for the next result. A fresh numpy array of the default
// gear's traces (140-490 kB a column) comes from glibc as new pages, and faulting them in cost more than filling
// them (docs/performance.md, "Python"); a script simulating in a loop frees a result's columns and asks for the same
// sizes again. Each column made here owns a block (its base is a capsule); when Python frees the column the block goes
// back to a cache (at most kCachedBytes in all) and the next column of that size reuses its warm pages.
#pragma once

#include <pybind11/numpy.h>

#include <cstddef>

namespace geartopo::python {

inline constexpr std::size_t kCachedBytes = std::size_t{64} << 20; ///< 64 MiB: a few dense results

/// A 1-D C-contiguous writable array of n elements of `dtype`, uninitialised, its memory from the cache.
pybind11::array cached_array(const pybind11::dtype& dtype, std::size_t n);

} // namespace geartopo::python
