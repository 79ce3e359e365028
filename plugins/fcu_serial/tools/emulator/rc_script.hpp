// emulator/rc_script.hpp: the emulated pilot's transmitter, scripted over time (the
// emulator's --rc option), and the receiver frame it produces.
//
// Script: steps "T key=value key=value; T key=value ...", T in seconds since the emulator
// started (ascending); each value holds until a later step changes it. Keys:
//   roll, pitch, yaw   stick, -1..1 (transmitter channels 1, 2, 4: AETR)
//   throttle           stick, 0..1 (channel 3)
//   aux1 .. aux4       switch or knob, -1..1 (channels 5..8)
//   lost               1: the receiver reports failsafe (SBUS failsafe flag), 0: back
// "none" instead of a script: no receiver at all (no RC frames).
// Start values: sticks centred, throttle 0, aux -1, not lost. PWM = 1500 + 500 v for -1..1
// values, 1000 + 1000 v for the throttle; the firmware reads (PWM - 1000) / 1000 (rc.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "tern_fcu_serial/firmware.hpp"

namespace tern::fcu::emulator {

struct Transmitter {
  std::array<double, 8> value{0, 0, 0, 0, -1, -1, -1, -1};  ///< channel 1..8 in script units
  bool lost = false;
};

class RcScript {
 public:
  /// Parses a script; throws std::invalid_argument naming the step and key at fault.
  explicit RcScript(const std::string& text);
  bool receiver() const { return receiver_; }
  /// The transmitter at time t (ns since start).
  Transmitter at(std::int64_t t) const;
  /// The receiver frame the board hands the firmware for transmitter x.
  static firmware::RcFrame frame(const Transmitter& x);

 private:
  struct Step {
    std::int64_t t = 0;
    std::vector<std::pair<int, double>> set;  ///< channel (0..7, or -1 for lost), value
  };
  std::vector<Step> steps_;
  bool receiver_ = true;
};

}  // namespace tern::fcu::emulator
