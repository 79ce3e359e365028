// core/apps/sysid/sysid_output.hpp: what `tern sysid` writes (docs/system-identification.md):
//   DIR/aircraft.yaml  the prior file with the identified coefficients (tern's aircraft format,
//                      flyable as it is: mass, inertia, geometry, propulsion, servos and gear are
//                      the prior's)
//   DIR/sysid.json     every coefficient: estimate, standard error, prior, identified, method, note;
//                      each regression's fit; the drag figure; what produced the numbers
//   DIR/index.html     the table, and measured against predicted coefficients per axis
//   DIR/coefficients.csv  those coefficients over the longest airborne stretch, per sample
// and the table `tern sysid` prints. Errors: ConfigError naming the file (a prior not in tern's
// format, a file that cannot be written).
#pragma once

#include <filesystem>
#include <string>

#include "sysid/identify.hpp"

namespace tern::core::sysid {

/// What produced the result, for sysid.json and the page.
struct SysidProvenance {
  std::string log;       ///< the log identified
  std::string prior;     ///< the prior aircraft file
  std::string estimate;  ///< the estimator's run (tern replay) whose state was used
  std::string options;   ///< the options, one line
};

/// The result made loadable as tern's aircraft format: an estimate the format's loader refuses (its
/// plausible ranges, tern/aircraft.hpp: C_m_q 888, an Oswald factor 1.53) is not adopted: the
/// prior is kept for it, it counts as not identified, and a note says so. The loader is the judge,
/// so the ranges are declared once. Throws ConfigError when the prior itself does not load.
void keep_loadable(SysidResult& r, const SysidProvenance& from);

void write_sysid_outputs(const SysidResult& r, const SysidProvenance& from, const std::filesystem::path& dir);

/// `text` written to `file` (a command's output file); throws ConfigError "FILE: cannot write".
void write_text_file(const std::filesystem::path& file, const std::string& text);

/// The coefficient table as printed: name, prior, estimate, standard error, identified or why not
/// ("prior scaled: " for a held term r.held_scaled moved with its surface, else "prior kept: ").
std::string format_sysid_table(const SysidResult& r);

}  // namespace tern::core::sysid
