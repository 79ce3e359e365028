// aero_text.hpp: text helpers shared by the readers of `tern aero import` (VSPAERO, XFLR5, mass
// files). Internal to the tools; plain C++.
//
// Errors: fail() throws std::runtime_error "FILE: FIELD: WHAT" (one line).
#pragma once

#include <string>
#include <vector>

#include "tern/math.hpp"

namespace tern::aero::text {

/// Throws std::runtime_error("file: field: what").
[[noreturn]] void fail(const std::string& file, const std::string& field, const std::string& what);

/// The lines of a text file without trailing '\r'. Throws std::runtime_error "PATH: file ..." for
/// what is no regular file of at most kMaxTextFileBytes (tern/input_file.hpp read_text_file: a
/// directory, a device, a file too large) or cannot be read.
std::vector<std::string> read_lines(const std::string& path);

/// Whitespace-separated words of s.
std::vector<std::string> tokens(const std::string& s);

/// True (and v set) if the whole of s is a finite number.
bool to_double(const std::string& s, double& v);

/// s as a finite number, else fail(file, field, ...).
double number(const std::string& file, const std::string& field, const std::string& s);

std::string lower(std::string s);
std::string join(const std::vector<std::string>& v, const std::string& sep);

/// v with 6 significant digits.
std::string fmt(double v);

}  // namespace tern::aero::text
