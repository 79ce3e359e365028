// core/host/runners/isolation_channel.hpp: the shared memory between the host and one isolated instance
// (`isolate: true`), and what crosses it. Both sides include this file: the host's proxy
// (isolated_plugin.hpp) and the child process (isolate_main.cpp, binary `tern-isolate`).
//
// One segment per instance: an anonymous memfd (no name in /dev/shm that a crash could leave
// behind), created by the host, inherited by the child across exec, mapped by both. It holds a
// Header, then one slot per port (inputs first, then outputs, in the plugin's declaration
// order), each 64-byte aligned and type().size bytes long.
//
// Lockstep, one command at a time: the host writes the command (and the inputs' messages), posts
// `go`; the child runs it, writes the reply (outputs, log lines, an end-of-flight request, an
// error text), posts `done`. The two semaphores are Boost.Interprocess's process-shared
// semaphores placed in the segment; nothing else is shared while a command runs, so no other
// synchronisation is needed. Messages cross by memcpy, which is safe only for types that are
// plain bytes: the host refuses to isolate a plugin with a port whose type is not one of the
// standard messages that reflect::bitwise_copyable accepts (message_is_bitwise()).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <boost/interprocess/sync/interprocess_semaphore.hpp>

#include "tern/msg/control.hpp"
#include "tern/param.hpp"
#include "tern/time.hpp"

namespace tern::core::isolation {

/// What the host asks the child to do.
enum class Command : std::uint32_t {
  ready = 0,  ///< (the child's first reply: configured, ports checked)
  start = 1,
  step = 2,  ///< at Header::now
  reset = 3,
  take_over = 4,   ///< from Header::take_over
  stop = 5,        ///< replies with summary() in Header::text: records name, '\t', 8 bytes of double
  set_params = 6,  ///< Header::text holds encode_params()'s records
  quit = 7,        ///< the child exits 0
};

inline constexpr std::uint32_t kMagic = 0x4F534954u;  // "TISO"
inline constexpr std::size_t kMaxPorts = 64;
inline constexpr std::size_t kTextBytes = 16 * 1024;  ///< command argument or reply text
inline constexpr std::size_t kLogBytes = 64 * 1024;   ///< log lines of one command (more are counted, dropped)
inline constexpr std::size_t kNameBytes = 64;

/// One port: where its message lives in the segment, and its sequence number.
struct PortSlot {
  char name[kNameBytes];      ///< port name as declared
  std::uint64_t fingerprint;  ///< message layout fingerprint
  std::uint64_t offset;       ///< of the message bytes from the segment start
  std::uint32_t size;         ///< message bytes
  std::uint32_t bound;        ///< inputs: the host's input has a writer (0: unbound)
  std::uint32_t updated;      ///< inputs: the host's input is updated() (the child's is made to agree)
  std::uint64_t seq;          ///< the message's sequence number (0: none yet)
};

struct Header {
  boost::interprocess::interprocess_semaphore go{0}, done{0};
  std::uint32_t magic = kMagic;
  Command command = Command::ready;
  Nanos now = 0;
  msg::Actuators take_over{};
  std::uint32_t n_inputs = 0, n_outputs = 0;
  // the reply
  std::uint32_t failed = 0;         ///< the command threw: `text` says what
  std::uint32_t end_requested = 0;  ///< the plugin called end_flight(): end_reason, end_detail
  char end_reason[kNameBytes];
  char end_detail[1024];
  std::uint32_t text_used = 0;
  char text[kTextBytes];
  std::uint32_t log_used = 0;     ///< bytes of `log`: records [level u8][length u16][text]
  std::uint32_t log_dropped = 0;  ///< lines that did not fit
  char log[kLogBytes];
  PortSlot ports[kMaxPorts];  ///< n_inputs inputs, then n_outputs outputs
};

/// Bytes of a segment for ports of these message sizes (inputs then outputs).
std::size_t segment_size(const std::vector<std::size_t>& port_sizes);
/// Offset of port k's message (64-byte aligned, after the header and the messages before it).
std::vector<std::size_t> port_offsets(const std::vector<std::size_t>& port_sizes);

/// Whether a message type (by layout fingerprint) may cross by memcpy: one of the standard
/// messages (tern/msg/all.hpp) and reflect::bitwise_copyable.
bool message_is_bitwise(std::uint64_t fingerprint);

/// Writes `text` (cut to fit) into a fixed char array, NUL-terminated.
void put_text(char* dst, std::size_t cap, const std::string& text);

/// Parameter changes as records of the `set_params` command: [index u32][kind u8][value].
/// Throws std::length_error when they do not fit kTextBytes.
std::uint32_t encode_params(const std::vector<std::pair<std::uint32_t, ParamValue>>& changes, char* out);
std::vector<std::pair<std::uint32_t, ParamValue>> decode_params(const char* in, std::uint32_t used);

/// Appends one log line (dropped, and counted, when the area is full).
void append_log(Header& h, int level, const std::string& line);
/// The log lines of the last reply: (spdlog level, text).
std::vector<std::pair<int, std::string>> read_log(const Header& h);

}  // namespace tern::core::isolation
