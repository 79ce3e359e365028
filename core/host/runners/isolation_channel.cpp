#include "runners/isolation_channel.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "tern/msg/all.hpp"
#include "tern/reflect.hpp"

namespace tern::core::isolation {

namespace {

constexpr std::size_t kAlign = 64;

std::size_t align_up(std::size_t n) { return (n + kAlign - 1) / kAlign * kAlign; }

#define TERN_BITWISE_ENTRY_(T) {::tern::reflect::fingerprint<T>(), ::tern::reflect::bitwise_copyable<T>()},
struct Known {
  std::uint64_t fingerprint;
  bool bitwise;
};
constexpr Known kStandard[] = {TERN_STANDARD_MESSAGES(TERN_BITWISE_ENTRY_)};
#undef TERN_BITWISE_ENTRY_

class Writer {
 public:
  explicit Writer(char* out) : out_(out) {}
  void bytes(const void* p, std::size_t n) {
    if (n == 0) return;  // an empty text or list: its data() may be null, which memcpy must not get
    if (used_ + n > kTextBytes) throw std::length_error("parameter changes exceed the isolation channel's text area");
    std::memcpy(out_ + used_, p, n);
    used_ += n;
  }
  template <class T>
  void put(const T& v) {
    bytes(&v, sizeof v);
  }
  std::uint32_t used() const { return static_cast<std::uint32_t>(used_); }

 private:
  char* out_;
  std::size_t used_ = 0;
};

class Reader {
 public:
  Reader(const char* in, std::size_t used) : in_(in), used_(used) {}
  bool more() const { return at_ < used_; }
  void bytes(void* p, std::size_t n) {
    if (n == 0) return;  // into an empty text or list, whose data() may be null
    if (at_ + n > used_) throw std::runtime_error("truncated parameter record in the isolation channel");
    std::memcpy(p, in_ + at_, n);
    at_ += n;
  }
  template <class T>
  T get() {
    T v;
    bytes(&v, sizeof v);
    return v;
  }

 private:
  const char* in_;
  std::size_t used_, at_ = 0;
};

}  // namespace

std::vector<std::size_t> port_offsets(const std::vector<std::size_t>& port_sizes) {
  std::vector<std::size_t> out;
  std::size_t at = align_up(sizeof(Header));
  for (std::size_t s : port_sizes) {
    out.push_back(at);
    at += align_up(s);
  }
  return out;
}

std::size_t segment_size(const std::vector<std::size_t>& port_sizes) {
  std::size_t at = align_up(sizeof(Header));
  for (std::size_t s : port_sizes) at += align_up(s);
  return at;
}

bool message_is_bitwise(std::uint64_t fingerprint) {
  return std::any_of(std::begin(kStandard), std::end(kStandard), [&](const Known& k) { return k.fingerprint == fingerprint && k.bitwise; });
}

void put_text(char* dst, std::size_t cap, const std::string& text) {
  const std::size_t n = std::min(cap - 1, text.size());
  std::memcpy(dst, text.data(), n);
  dst[n] = '\0';
}

std::uint32_t encode_params(const std::vector<std::pair<std::uint32_t, ParamValue>>& changes, char* out) {
  Writer w(out);
  for (const auto& [index, value] : changes) {
    w.put(index);
    w.put(static_cast<std::uint8_t>(value.index()));
    if (const auto* b = std::get_if<bool>(&value)) {
      w.put(static_cast<std::uint8_t>(*b));
    } else if (const auto* i = std::get_if<std::int64_t>(&value)) {
      w.put(*i);
    } else if (const auto* d = std::get_if<double>(&value)) {
      w.put(*d);
    } else if (const auto* s = std::get_if<std::string>(&value)) {
      w.put(static_cast<std::uint32_t>(s->size()));
      w.bytes(s->data(), s->size());
    } else {
      const auto& v = std::get<std::vector<double>>(value);
      w.put(static_cast<std::uint32_t>(v.size()));
      w.bytes(v.data(), v.size() * sizeof(double));
    }
  }
  return w.used();
}

std::vector<std::pair<std::uint32_t, ParamValue>> decode_params(const char* in, std::uint32_t used) {
  std::vector<std::pair<std::uint32_t, ParamValue>> out;
  Reader r(in, used);
  while (r.more()) {
    const auto index = r.get<std::uint32_t>();
    const auto kind = r.get<std::uint8_t>();
    switch (kind) {
      case 0: out.emplace_back(index, r.get<std::uint8_t>() != 0); break;
      case 1: out.emplace_back(index, r.get<std::int64_t>()); break;
      case 2: out.emplace_back(index, r.get<double>()); break;
      case 3: {
        std::string s(r.get<std::uint32_t>(), '\0');
        r.bytes(s.data(), s.size());
        out.emplace_back(index, std::move(s));
        break;
      }
      case 4: {
        std::vector<double> v(r.get<std::uint32_t>());
        r.bytes(v.data(), v.size() * sizeof(double));
        out.emplace_back(index, std::move(v));
        break;
      }
      default: throw std::runtime_error("unknown parameter kind " + std::to_string(kind) + " in the isolation channel");
    }
  }
  return out;
}

void append_log(Header& h, int level, const std::string& line) {
  const std::size_t n = std::min<std::size_t>(line.size(), 0xffff);
  if (h.log_used + 3 + n > kLogBytes) {
    ++h.log_dropped;
    return;
  }
  char* p = h.log + h.log_used;
  p[0] = static_cast<char>(level);
  const auto len = static_cast<std::uint16_t>(n);
  std::memcpy(p + 1, &len, 2);
  std::memcpy(p + 3, line.data(), n);
  h.log_used += static_cast<std::uint32_t>(3 + n);
}

std::vector<std::pair<int, std::string>> read_log(const Header& h) {
  std::vector<std::pair<int, std::string>> out;
  const std::uint32_t used = std::min<std::uint32_t>(h.log_used, kLogBytes);
  for (std::uint32_t at = 0; at + 3 <= used;) {
    std::uint16_t len = 0;
    std::memcpy(&len, h.log + at + 1, 2);
    if (at + 3 + len > used) break;
    out.emplace_back(static_cast<int>(static_cast<unsigned char>(h.log[at])), std::string(h.log + at + 3, len));
    at += 3 + len;
  }
  return out;
}

}  // namespace tern::core::isolation
