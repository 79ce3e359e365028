// tests/plugins/misbehave.hpp: deliberate failures of a test plugin's step, for the isolation
// and watchdog tests (issue 19): `segv` writes through a null pointer (SIGSEGV), `hang` loops
// for ever, `exit` ends the process with status 3. Other modes do nothing here.
#pragma once

#include <csignal>
#include <cstdlib>
#include <string>

namespace tern_test {

// Not instrumented by UndefinedBehaviorSanitizer (make sanitize): the null store is the point, and
// UBSan's halt_on_error would end the process with status 1 before the SIGSEGV the tests expect;
// the signal's default action is restored first, for AddressSanitizer's own SIGSEGV handler would
// report and exit with status 1 too.
#if defined(__GNUC__)
__attribute__((no_sanitize("undefined")))
#endif
inline void
misbehave(const std::string& mode) {
  if (mode == "segv") {
    std::signal(SIGSEGV, SIG_DFL);
    volatile int* volatile nowhere = nullptr;
    *nowhere = 1;
  } else if (mode == "hang") {
    for (volatile bool forever = true; forever;) {
    }
  } else if (mode == "exit") {
    std::_Exit(3);
  }
}

}  // namespace tern_test
