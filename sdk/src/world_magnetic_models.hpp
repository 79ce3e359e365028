// world_magnetic_models.hpp (private to libtern_sdk): the WMM coefficient tables as the build
// transcribes them from data/magnetic/*.COF (sdk/cmake/wmm_cof_to_cpp.cmake writes
// world_magnetic_models.cpp in the build tree). Each table is one COF file: its header (epoch,
// model name, release date) and its rows "n m g h gdot hdot" in the file's order, n = 1..N,
// m = 0..n (the generator refuses any other order). Read by magnetic_model.cpp.
#pragma once

#include <cstddef>

namespace tern::wmm {

/// One row of a COF file: Schmidt semi-normalised Gauss coefficients of degree n and order m.
struct CofRow {
  int n, m;
  double g, h;        ///< main field at the epoch, nT
  double gdot, hdot;  ///< secular variation, nT/yr
};

/// One COF file.
struct CofModel {
  const char* name;          ///< the header's model name, e.g. "WMM-2025"
  double epoch;              ///< decimal year of the coefficients' epoch
  const char* release_date;  ///< the header's date, MM/DD/YYYY
  const char* file;          ///< the COF file it came from (data/magnetic/)
  const CofRow* rows;
  std::size_t row_count;
};

extern const CofModel kModels[];  ///< in the order of their files' names
extern const std::size_t kModelCount;

}  // namespace tern::wmm
