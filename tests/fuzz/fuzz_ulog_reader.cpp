// fuzz_ulog_reader: libFuzzer target for the PX4 ULog reader (core/apps/import/ulog_reader.hpp), as
// `tern import ulog` reads a .ulg: the header and definitions (flag bits, formats, info, multi info,
// parameters, default parameters), then the data section streamed into handlers that take every
// subscription's flattened layout and every field of every data message apart. Any bytes: the
// reader gives values or throws UlogError (one line), never crashes, reads out of bounds, loops or
// allocates without bound (a format nesting arrays of arrays).
#include <cstdint>
#include <stdexcept>
#include <string>

#include "fuzz_input.hpp"
#include "import/ulog_reader.hpp"

using namespace tern::core::ulog;

namespace {

void touch(const Value& v) {
  (void)v.text();
  try {
    (void)v.number();
  } catch (const std::invalid_argument&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = tern::fuzz::as_file(data, size, ".ulg");
  try {
    Reader r(file);
    for (const auto& [key, v] : r.info()) touch(v);
    for (const auto& [key, v] : r.initial_parameters()) touch(v);
    for (const auto& [bit, params] : r.default_parameters())
      for (const auto& [key, v] : params) touch(v);
    for (const auto& [key, list] : r.info_multiple())
      for (const auto& parts : list)
        for (const auto& v : parts) touch(v);
    DataHandler h;
    h.on_subscription = [](const Subscription& s) {
      // the layout: fields in order, inside the message, each found by its name
      std::size_t end = 0;
      for (const Field& f : s.fields()) {
        if (f.offset < end) __builtin_trap();
        end = f.offset + base_type_size(f.type);
        if (s.field(f.name) == nullptr) __builtin_trap();
      }
      if (end != s.size() || s.size() > s.padded_size()) __builtin_trap();
    };
    h.on_data = [](const DataMessage& m) {
      for (const Field& f : m.subscription().fields()) {
        (void)m.value(f);
        (void)m.integer(f);
      }
      (void)m.timestamp();
    };
    h.on_logged_string = [](const LoggedString& s) { (void)s.level_name(); };
    h.on_parameter = [](const std::string&, const Value& v, std::uint64_t) { touch(v); };
    const UlogDataStats stats = r.read_data(h);
    // data that ends at a corrupt header: the rest of the file, named in one more warning
    if (stats.unread_bytes != 0 &&
        (stats.unread_from + stats.unread_bytes != size || stats.first_problem_offset > stats.unread_from || stats.unread_reason.empty()))
      __builtin_trap();
    const auto warnings = stats.warnings(file.string());
    if (stats.unread_bytes != 0 && warnings.back().find(" bytes not read)") == std::string::npos) __builtin_trap();
  } catch (const UlogError&) {
  }
  return 0;
}
