// geartopo Python module — tables as dicts of numpy arrays (one array per column, the CSV files' column names) and
// back. Each array is allocated once (column_memory.hpp) and filled in place: the only copy is from the library's records.
#pragma once

#include "column_memory.hpp"

#include "geartopo/core/flank.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/grinding/topology_csv.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace geartopo::python {

/// A 1-D array of n elements, uninitialised, its memory from the cache of column_memory.hpp.
template <class T>
pybind11::array_t<T> new_column(std::size_t n) {
  return pybind11::array_t<T>(cached_array(pybind11::dtype::of<T>(), n));
}

inline constexpr std::size_t kFlankWidth = 5; ///< "right"
inline constexpr std::size_t kTraceWidth = 7; ///< "profile"

/// A 1-D numpy array of n fixed-width unicode strings (dtype '<U{width}'), filled word by word in place: flank and
/// trace names (ASCII, at most width characters).
class WordColumn {
public:
  WordColumn(std::size_t n, std::size_t width);
  void set(std::size_t i, std::string_view word) {
    char32_t* out = data_ + i * width_;
    std::size_t c = 0;
    for (; c < word.size() && c < width_; ++c) out[c] = static_cast<char32_t>(static_cast<unsigned char>(word[c]));
    for (; c < width_; ++c) out[c] = 0;
  }
  pybind11::array array() const { return array_; }

private:
  pybind11::array array_;
  std::size_t width_;
  char32_t* data_;
};

/// topology.csv's columns of simulated flanks: tooth, flank, row, col, diameter_mm, z_mm, deviation_um, design_um
/// (and roll_length_mm, which the file leaves out), from the grid or the dense grid.
pybind11::dict topology_columns(const std::vector<grinding::FlankTopology>& topo, grinding::GridKind kind);
/// traces.csv's columns: tooth, flank, trace, roll_length_mm, diameter_mm, z_mm, deviation_um, design_um.
pybind11::dict traces_columns(const std::vector<grinding::FlankTopology>& topo);
/// The same as topology_columns for rows (a synthetic measurement: measured.csv's columns).
pybind11::dict topology_row_columns(const std::vector<grinding::TopologyRow>& rows);

/// A column of a user's dict: `key` must be there (InputError naming `source` and the key otherwise), with `n`
/// elements (n < 0: any; the length is returned through n).
pybind11::array_t<double> double_column(const pybind11::dict& d, const char* key, const std::string& source, long long& n);
pybind11::array_t<int> int_column(const pybind11::dict& d, const char* key, const std::string& source, long long& n);
/// A column of words ("left", "right", …) as strings.
std::vector<std::string> word_list(const pybind11::dict& d, const char* key, const std::string& source, long long& n);

/// The flanks of simulate()'s dict (its grid columns and its "traces" and "dense" dicts) or of a traces dict (with a
/// "trace" column: synth(format="traces")), for the evaluator: one
/// FlankTopology per (tooth, flank) in order of first appearance, every value as it was simulated. Throws InputError
/// naming `source` and the column for a missing or short column or an unknown flank or trace name.
std::vector<grinding::FlankTopology> topology_from_columns(const pybind11::dict& topo, const std::string& source);

} // namespace geartopo::python
