// fuzz_text_table: libFuzzer target for the text tables `tern import` reads (core/apps/import/
// text_table.hpp): InertialNav's whitespace-separated .txt and the ALFA dataset's rostopic CSV
// (header line, comma-separated), every row taken apart cell by cell as numbers and integers; and
// for the same bytes the readers of `tern aero import` (sdk/aero, tern/aero/import.hpp): a VSPAERO
// .stab and .polar and an XFLR5 stability-polar log. Any bytes: values, or one error line
// (ImportError; the aero readers' std::runtime_error) naming the file; never a crash, an
// out-of-bounds read, a hang or another exception.
#include <cstdint>
#include <stdexcept>
#include <string>

#include "fuzz_input.hpp"
#include "import/text_table.hpp"
#include "tern/aero/import.hpp"

using namespace tern::core;

namespace {

void read_all(const std::filesystem::path& file, TextTable::Separator sep, std::size_t min_cells) {
  try {
    TextTable t(file, sep);
    if (sep == TextTable::Separator::comma) {
      try {
        (void)t.column("field.header.stamp");
      } catch (const ImportError&) {
      }
    }
    while (t.next(min_cells)) {
      if (t.cells() < min_cells) __builtin_trap();
      for (std::size_t i = 0; i < t.cells(); ++i) {
        (void)t.text(i);
        try {
          (void)t.number(i);
        } catch (const ImportError&) {
        }
        try {
          (void)t.integer(i);
        } catch (const ImportError&) {
        }
      }
    }
  } catch (const ImportError&) {
  }
}

/// An aero reader's error: one line naming the file.
void aero_error(const std::runtime_error& e, const std::string& file) {
  if (std::string(e.what()).rfind(file + ": ", 0) != 0) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = tern::fuzz::as_file(data, size, ".txt");
  read_all(file, TextTable::Separator::whitespace, 0);
  read_all(file, TextTable::Separator::whitespace, 8);  // IMU.txt's columns
  read_all(file, TextTable::Separator::comma, 0);
  const std::string path = file.string();
  try {
    (void)tern::aero::parse_vspaero_stab(path);
  } catch (const std::runtime_error& e) {
    aero_error(e, path);
  }
  try {
    tern::aero::VspaeroOptions o;
    o.controls = {"-ConGrp_1", "none", "rudder"};
    o.aoa_deg = 2.0;
    (void)tern::aero::parse_vspaero_stab(path, o);
  } catch (const std::runtime_error& e) {
    aero_error(e, path);
  }
  try {
    (void)tern::aero::parse_vspaero_polar(path, 8.0);
  } catch (const std::runtime_error& e) {
    aero_error(e, path);
  }
  try {
    (void)tern::aero::parse_xflr5(path, "elevator");
  } catch (const std::runtime_error& e) {
    aero_error(e, path);
  }
  return 0;
}
