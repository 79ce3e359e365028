// core/host/graph/elf_check.hpp: is a file a shared object this host can load? Asked before dlopen.
//
// dlopen maps a shared object and touches its pages: a file cut short (a copy or a build that
// was interrupted) raises SIGBUS inside dlopen, which kills the process with no message; a file
// built for another architecture is reported by the dynamic loader as "No such file or
// directory". check_elf reads only the headers (with read(2), never a mapping) and turns each of
// these into one line. The ELF structures are glibc's <elf.h> (System V ABI, "ELF-64 Object File
// Format").
#pragma once

#include <filesystem>

namespace tern::core {

/// Checks that `path` is a complete 64-bit ELF shared object (ET_DYN) for this host's machine
/// and byte order: size, magic number, class, data encoding, type, machine, and that its program
/// headers, loadable segments and section headers lie inside the file. Throws ConfigError
/// "cannot load '<path>': <what is wrong>".
void check_elf(const std::filesystem::path& path);

}  // namespace tern::core
