#include "graph/elf_check.hpp"

#include <elf.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "config/error.hpp"

namespace tern::core {

namespace {

namespace fs = std::filesystem;

struct Fd {
  int fd;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

bool read_at(int fd, void* dst, std::size_t n, std::uint64_t offset) {
  return ::pread(fd, dst, n, static_cast<off_t>(offset)) == static_cast<ssize_t>(n);
}

std::string machine_name(Elf64_Half m) {
  switch (m) {
    case EM_X86_64: return "x86-64";
    case EM_AARCH64: return "AArch64";
    case EM_ARM: return "32-bit ARM";
    case EM_386: return "32-bit x86";
    case EM_RISCV: return "RISC-V";
    case EM_PPC64: return "PowerPC 64";
    case EM_S390: return "IBM Z";
    default: return fmt::format("machine {}", m);
  }
}

std::string type_name(Elf64_Half t) {
  switch (t) {
    case ET_REL: return "an object file (ET_REL, not linked)";
    case ET_EXEC: return "an executable (ET_EXEC)";
    case ET_CORE: return "a core dump (ET_CORE)";
    default: return fmt::format("ELF type {}", t);
  }
}

/// The ELF header of this process's own executable: the machine and byte order plugins need.
const std::optional<Elf64_Ehdr>& host_header() {
  static const std::optional<Elf64_Ehdr> h = [] {
    const Fd f{::open("/proc/self/exe", O_RDONLY | O_CLOEXEC)};
    Elf64_Ehdr e{};
    if (f.fd < 0 || !read_at(f.fd, &e, sizeof e, 0)) return std::optional<Elf64_Ehdr>();
    return std::optional<Elf64_Ehdr>(e);
  }();
  return h;
}

/// What is wrong with the identification and header fields ("" if nothing).
std::string header_problem(const Elf64_Ehdr& e) {
  if (std::memcmp(e.e_ident, ELFMAG, SELFMAG) != 0)
    return fmt::format("not an ELF file (it starts with {:02x} {:02x} {:02x} {:02x}, not 7f 45 4c 46)", e.e_ident[0], e.e_ident[1],
                       e.e_ident[2], e.e_ident[3]);
  if (e.e_ident[EI_CLASS] != ELFCLASS64)
    return e.e_ident[EI_CLASS] == ELFCLASS32 ? "a 32-bit ELF file; this host loads 64-bit shared objects"
                                             : fmt::format("unknown ELF class {}", e.e_ident[EI_CLASS]);
  const auto& host = host_header();
  if (host && e.e_ident[EI_DATA] != host->e_ident[EI_DATA])
    return fmt::format("byte order {}, this host's is {}", e.e_ident[EI_DATA] == ELFDATA2MSB ? "big-endian" : "little-endian",
                       host->e_ident[EI_DATA] == ELFDATA2MSB ? "big-endian" : "little-endian");
  if (host && e.e_machine != host->e_machine)
    return fmt::format("built for {} (e_machine {}), this host is {}", machine_name(e.e_machine), e.e_machine,
                       machine_name(host->e_machine));
  if (e.e_type != ET_DYN) return type_name(e.e_type) + ", not a shared object (ET_DYN)";
  return "";
}

std::string truncated(const char* what, std::uint64_t end, std::uint64_t size) {
  return fmt::format("truncated: {} end at byte {}, the file has {} bytes (an interrupted copy or build?)", what, end, size);
}

/// What is wrong with the extents of the headers and segments ("" if nothing).
std::string extent_problem(int fd, const Elf64_Ehdr& e, std::uint64_t size) {
  if (e.e_phnum > 0 && e.e_phentsize != sizeof(Elf64_Phdr))
    return fmt::format("corrupt: program header entries of {} bytes, not {}", e.e_phentsize, sizeof(Elf64_Phdr));
  const std::uint64_t ph_end = e.e_phoff + std::uint64_t{e.e_phnum} * sizeof(Elf64_Phdr);
  if (ph_end > size) return truncated("its program headers", ph_end, size);
  for (Elf64_Half i = 0; i < e.e_phnum; ++i) {
    Elf64_Phdr ph{};
    if (!read_at(fd, &ph, sizeof ph, e.e_phoff + std::uint64_t{i} * sizeof ph)) return "unreadable program header";
    if (ph.p_type != PT_LOAD && ph.p_type != PT_DYNAMIC) continue;
    if (ph.p_offset + ph.p_filesz > size)
      return truncated(ph.p_type == PT_LOAD ? "its loadable segments" : "its dynamic section", ph.p_offset + ph.p_filesz, size);
  }
  const std::uint64_t sh_end = e.e_shoff + std::uint64_t{e.e_shnum} * e.e_shentsize;
  if (e.e_shoff != 0 && sh_end > size) return truncated("its section headers", sh_end, size);
  return "";
}

}  // namespace

void check_elf(const fs::path& path) {
  auto fail = [&](const std::string& what) { throw ConfigError(fmt::format("cannot load '{}': {}", path.string(), what)); };
  const Fd f{::open(path.c_str(), O_RDONLY | O_CLOEXEC)};
  if (f.fd < 0) fail(std::strerror(errno));
  struct stat st {};
  if (::fstat(f.fd, &st) != 0) fail(std::strerror(errno));
  if (!S_ISREG(st.st_mode)) fail("not a regular file");
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size == 0) fail("empty file (0 bytes)");
  Elf64_Ehdr e{};
  const std::size_t head = std::min<std::uint64_t>(size, sizeof e);
  if (!read_at(f.fd, &e, head, 0)) fail(std::strerror(errno));
  if (head < sizeof e && (head < SELFMAG || std::memcmp(e.e_ident, ELFMAG, SELFMAG) != 0))
    fail(fmt::format("not an ELF file ({} bytes)", size));
  if (head < sizeof e) fail(fmt::format("truncated: {} bytes, less than an ELF header ({} bytes)", size, sizeof e));
  if (const std::string p = header_problem(e); !p.empty()) fail(p);
  if (const std::string p = extent_problem(f.fd, e, size); !p.empty()) fail(p);
}

}  // namespace tern::core
