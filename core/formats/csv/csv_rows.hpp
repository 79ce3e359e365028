// core/formats/csv/csv_rows.hpp: a topic's CSV table as the flight log writes it (flight_log.hpp),
// shared by the log's writer thread and `tern export csv` so that both write the same bytes.
//
// Header: "t [s],<name> [<unit>],..."; one row per message: the flight time as exact decimal
// seconds from integer ns ("<s>.<9 digits>"), then each column with std::to_chars (shortest
// round-trip for floating point: a logged double reads back bit-exact), bools as 0/1.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "tern/reflect.hpp"
#include "tern/time.hpp"

namespace tern::core {

/// Enough for any cell: "-1.2345678901234567e-308" and any 64-bit integer fit.
inline constexpr std::size_t kMaxCellChars = 32;

/// "t [s],a [m],b [],...\n"
std::string csv_header(const std::vector<reflect::Column>& columns);
/// Writes `t` (ns) as "<s>.<9 digits>" at p; returns the end.
char* put_csv_time(char* p, Nanos t);
/// Formats `records` (each: int64 flight time in ns, then `msg_size` bytes of a message laid out
/// as `columns` say) as CSV rows into `out`, grown to `capacity` when needed; returns the number
/// of characters written.
std::size_t format_csv_rows(const std::vector<reflect::Column>& columns, std::size_t msg_size, std::string_view records,
                            std::unique_ptr<char[]>& out, std::size_t& capacity);

}  // namespace tern::core
