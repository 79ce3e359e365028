// Reading a file someone hands tern, and echoing what it says (tern/input_file.hpp).
#include "tern/input_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>

namespace tern {

namespace fs = std::filesystem;

namespace {

const char* kind_name(fs::file_type t) {
  switch (t) {
    case fs::file_type::character: return "a character device";
    case fs::file_type::block: return "a block device";
    case fs::file_type::fifo: return "a FIFO";
    case fs::file_type::socket: return "a socket";
    default: return "not a file";
  }
}

}  // namespace

std::string input_file_problem(const fs::path& file, std::uintmax_t max_bytes) {
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);  // follows symlinks: a link to /dev/zero is a device
  if (st.type() == fs::file_type::not_found) return "does not exist";
  if (ec) return "cannot be read: " + ec.message();
  if (st.type() == fs::file_type::directory) return "is a directory";
  if (st.type() != fs::file_type::regular) return std::string("is not a regular file (") + kind_name(st.type()) + ")";
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec) return "cannot be read: " + ec.message();
  if (size > max_bytes)
    return "is " + std::to_string(size) + " bytes, more than the " + std::to_string(max_bytes) + " bytes tern reads of one";
  return "";
}

std::string read_text_file(const fs::path& file, const char* what, std::uintmax_t max_bytes) {
  const std::string name = printable(file.string());
  if (const std::string p = input_file_problem(file, max_bytes); !p.empty()) throw std::runtime_error(name + ": " + what + " " + p);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(name + ": cannot read the " + what + ": " + std::strerror(errno));
  std::string text;
  std::vector<char> block(1 << 16);
  while (in.read(block.data(), static_cast<std::streamsize>(block.size())) || in.gcount() > 0) {
    text.append(block.data(), static_cast<std::size_t>(in.gcount()));
    if (text.size() > max_bytes)  // grew while being read
      throw std::runtime_error(name + ": " + what + " is more than the " + std::to_string(max_bytes) + " bytes tern reads of one");
  }
  if (in.bad()) throw std::runtime_error(name + ": cannot read the " + what + ": " + std::strerror(errno));
  return text;
}

void check_yaml_size(const YAML::Node& root, const fs::path& file) {
  std::vector<YAML::Node> pending{root};
  std::size_t seen = 0;
  while (!pending.empty()) {
    const YAML::Node n = pending.back();
    pending.pop_back();
    if (++seen > kMaxYamlNodes)
      throw std::runtime_error(printable(file.string()) + ": more than " + std::to_string(kMaxYamlNodes) +
                               " YAML nodes once its aliases are expanded (an alias bomb?)");
    if (n.IsSequence()) {
      for (const auto& item : n) pending.push_back(item);
    } else if (n.IsMap()) {
      for (const auto& kv : n) {
        pending.push_back(kv.first);
        pending.push_back(kv.second);
      }
    }
  }
}

YAML::Node load_yaml_file(const fs::path& file, const char* what) {
  const std::string text = read_text_file(file, what);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::DeepRecursion& e) {  // yaml-cpp's own words: "bad file"
    throw std::runtime_error(printable(file.string()) + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                             ": YAML nested too deeply (more than yaml-cpp's parser takes)");
  } catch (const YAML::Exception& e) {
    const std::string at = e.mark.is_null() ? "" : ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1);
    throw std::runtime_error(printable(file.string()) + at + ": YAML syntax error: " + printable(e.msg));
  }
  check_yaml_size(root, file);
  return root;
}

namespace {

/// The length of the UTF-8 sequence of a character at text[i] (1 to 4 bytes: a lead byte and its
/// continuation bytes), or 0 when the bytes there are no such sequence (a stray continuation byte,
/// a lead byte cut short, 0xC0, 0xC1 or 0xF5..0xFF: RFC 3629, section 4).
std::size_t utf8_length(std::string_view text, std::size_t i) {
  const auto c = static_cast<unsigned char>(text[i]);
  const std::size_t n = c < 0x80 ? 1 : (c >= 0xc2 && c <= 0xdf) ? 2 : (c >= 0xe0 && c <= 0xef) ? 3 : (c >= 0xf0 && c <= 0xf4) ? 4 : 0;
  if (n == 0 || i + n > text.size()) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((static_cast<unsigned char>(text[i + k]) & 0xc0) != 0x80) return 0;
  return n;
}

}  // namespace

std::string printable(std::string_view text, std::size_t max_chars) {
  std::string out;
  std::size_t n = 0;
  const auto escape = [&out](unsigned char c) {
    char hex[8];
    std::snprintf(hex, sizeof hex, "\\x%02x", c);
    out += hex;
  };
  for (std::size_t i = 0; i < text.size(); ++n) {
    if (n == max_chars) return out + "...";
    const auto c = static_cast<unsigned char>(text[i]);
    const std::size_t len = utf8_length(text, i);
    const bool c1 = len == 2 && c == 0xc2 && static_cast<unsigned char>(text[i + 1]) < 0xa0;  // U+0080..U+009F: C1 controls (CSI)
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c1) {
      escape(static_cast<unsigned char>(text[i + 1]));
    } else if (len == 0 || c < 0x20 || c == 0x7f) {
      escape(c);  // a control character, or a byte of no UTF-8 character (0x9b alone: CSI to an 8-bit terminal)
    } else {
      out.append(text.substr(i, len));
    }
    i += len == 0 ? 1 : len;
  }
  return out;
}

}  // namespace tern
