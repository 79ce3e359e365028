// joystick: a USB joystick, game controller or RC transmitter in joystick mode as the pilot of a
// simulated flight (`tern fly --realtime` with this plugin in the mission), through SDL2's game
// controller API (Debian libsdl2-dev).
//
// Ports
//   out pilot   msg::Rc   every step: sticks (sticks.hpp: mapping, reversal, deadband, expo) and
//                         switches: manual_button toggles the override (the controller's manual
//                         modes), angle_button toggles aux channel 0 (+1 / -1: angle mode when the
//                         controller's angle_mode_aux is 0). sim_aero reports it on `rc`.
// start() opens controller number `device` and throws, naming what SDL sees, when there is none
// (the flight does not start: plug one in, or fly from the console, `--console`). A controller
// unplugged in flight raises the receiver's failsafe (failsafe true, override off, sticks centred).
#pragma once

#include <cstdint>

#include "tern/joystick/sticks.hpp"
#include "tern/plugin.hpp"

struct _SDL_GameController;

namespace tern::joystick {

class JoystickPlugin final : public Plugin {
 public:
  ~JoystickPlugin() override;
  void configure() override;
  void start() override;
  void step(Nanos now) override;
  void stop() override;

 private:
  StickShaping shaping() const;
  void close();

  Output<msg::Rc> pilot_;
  Param<std::int64_t> device_, roll_axis_, pitch_axis_, yaw_axis_, throttle_axis_, manual_button_, angle_button_;
  Param<bool> reverse_roll_, reverse_pitch_, reverse_yaw_, reverse_throttle_;
  Param<double> deadband_, expo_;
  _SDL_GameController* pad_ = nullptr;
  bool sdl_up_ = false;
  bool manual_ = false, angle_ = false;  // the toggles' state
  bool manual_was_down_ = false, angle_was_down_ = false;
};

}  // namespace tern::joystick
