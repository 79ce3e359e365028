// Numbers in the mission reader's and checker's messages.
#pragma once

#include <cstdio>
#include <string>

namespace tern::path {

/// `v` with up to 10 significant digits ("1457", "40.2499718"), or with `decimals` decimals.
inline std::string number_text(double v, int decimals = -1) {
  char b[64];
  if (decimals < 0)
    std::snprintf(b, sizeof b, "%.10g", v);
  else
    std::snprintf(b, sizeof b, "%.*f", decimals, v);
  return b;
}

}  // namespace tern::path
