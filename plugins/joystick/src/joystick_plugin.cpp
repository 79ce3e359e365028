// joystick adapter: SDL2 game controller -> msg::Rc on `pilot`. See joystick_plugin.hpp.
#include "joystick_plugin.hpp"

#include <SDL.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

namespace tern::joystick {
namespace {

std::string what_sdl_sees() {
  const int n = SDL_NumJoysticks();
  if (n <= 0) return "SDL sees no joystick (is one plugged in? can this user read /dev/input/event*?)";
  std::string s = "SDL sees " + std::to_string(n) + ":";
  for (int i = 0; i < n; ++i) {
    const char* name = SDL_JoystickNameForIndex(i);
    s += " [" + std::to_string(i) + "] " + (name ? name : "?") +
         (SDL_IsGameController(i) ? "" : " (no game-controller mapping: set SDL_GAMECONTROLLERCONFIG)");
  }
  return s;
}

}  // namespace

JoystickPlugin::~JoystickPlugin() { close(); }

void JoystickPlugin::configure() {
  declare(pilot_, "pilot", "the pilot's sticks and switches from the game controller");
  declare(device_, "device", std::int64_t{0}, ParamSpec("", 0, 15, "game controller number (SDL's joystick index)").start_only());
  const ParamSpec axis("", 0, 5, "SDL game-controller axis: 0 left x, 1 left y, 2 right x, 3 right y, 4 left trigger, 5 right trigger");
  auto with = [](ParamSpec s, const std::string& d) {
    s.description = d + " (" + s.description + ")";
    return s;
  };
  declare(roll_axis_, "roll_axis", std::int64_t{2}, with(axis, "axis of the roll stick"));
  declare(pitch_axis_, "pitch_axis", std::int64_t{3}, with(axis, "axis of the pitch stick"));
  declare(yaw_axis_, "yaw_axis", std::int64_t{0}, with(axis, "axis of the rudder stick"));
  declare(throttle_axis_, "throttle_axis", std::int64_t{1}, with(axis, "axis of the throttle stick"));
  declare(reverse_roll_, "reverse_roll", false, ParamSpec("", 0, 0, "negate the roll axis"));
  declare(reverse_pitch_, "reverse_pitch", false, ParamSpec("", 0, 0, "negate the pitch axis (SDL: stick back is +, nose up)"));
  declare(reverse_yaw_, "reverse_yaw", false, ParamSpec("", 0, 0, "negate the rudder axis"));
  declare(reverse_throttle_, "reverse_throttle", true, ParamSpec("", 0, 0, "negate the throttle axis (SDL: stick up is -)"));
  declare(deadband_, "deadband", 0.05, ParamSpec("", 0.0, 0.5, "stick travel around centre read as centre, fraction of full"));
  declare(expo_, "expo", 0.3, ParamSpec("", 0.0, 1.0, "roll, pitch, yaw curve: (1 - expo) x + expo x^3"));
  declare(manual_button_, "manual_button", std::int64_t{9},
          ParamSpec("", 0, 20, "button toggling manual (the override switch); SDL: 0 A, 1 B, 2 X, 3 Y, 9 left shoulder, 10 right"));
  declare(angle_button_, "angle_button", std::int64_t{10}, ParamSpec("", 0, 20, "button toggling angle mode (aux channel 0)"));
}

void JoystickPlugin::start() {
  close();
  manual_ = angle_ = manual_was_down_ = angle_was_down_ = false;
  SDL_SetHint(SDL_HINT_JOYSTICK_ALLOW_BACKGROUND_EVENTS, "1");
  if (SDL_Init(SDL_INIT_GAMECONTROLLER) != 0) throw std::runtime_error(std::string("joystick: SDL cannot start: ") + SDL_GetError());
  sdl_up_ = true;
  SDL_GameControllerEventState(SDL_IGNORE);  // polled in step(), no event loop
  const int idx = static_cast<int>(device_());
  if (idx >= SDL_NumJoysticks() || !SDL_IsGameController(idx))
    throw std::runtime_error("joystick: no game controller number " + std::to_string(idx) + ": " + what_sdl_sees() +
                             ". Fly from the browser instead: tern fly --realtime --console");
  pad_ = SDL_GameControllerOpen(idx);
  if (pad_ == nullptr) throw std::runtime_error(std::string("joystick: cannot open controller: ") + SDL_GetError());
  log().info("joystick: {}", SDL_GameControllerName(pad_));
}

StickShaping JoystickPlugin::shaping() const {
  StickShaping s;
  s.map = {StickMap{static_cast<int>(roll_axis_()), reverse_roll_()}, StickMap{static_cast<int>(pitch_axis_()), reverse_pitch_()},
           StickMap{static_cast<int>(yaw_axis_()), reverse_yaw_()}, StickMap{static_cast<int>(throttle_axis_()), reverse_throttle_()}};
  s.deadband = deadband_();
  s.expo = expo_();
  return s;
}

void JoystickPlugin::step(Nanos now) {
  if (pad_ == nullptr) return;
  SDL_GameControllerUpdate();
  msg::Rc rc;
  rc.stamp = now;
  if (!SDL_GameControllerGetAttached(pad_)) {
    rc.failsafe = true;  // the receiver lost the transmitter
    pilot_.publish(rc);
    return;
  }
  std::array<double, 6> axes{};
  for (int a = 0; a < 6; ++a)
    axes[static_cast<std::size_t>(a)] = std::max(-1.0, SDL_GameControllerGetAxis(pad_, static_cast<SDL_GameControllerAxis>(a)) / 32767.0);
  const Sticks s = sticks_from_axes(axes, shaping());
  const auto toggled = [this](std::int64_t button, bool& was_down) {
    const bool down = SDL_GameControllerGetButton(pad_, static_cast<SDL_GameControllerButton>(button)) != 0;
    const bool press = down && !was_down;
    was_down = down;
    return press;
  };
  if (toggled(manual_button_(), manual_was_down_)) manual_ = !manual_;
  if (toggled(angle_button_(), angle_was_down_)) angle_ = !angle_;
  rc.roll = s.roll;
  rc.pitch = s.pitch;
  rc.yaw = s.yaw;
  rc.throttle = s.throttle;
  rc.rc_override = manual_;
  rc.aux[0] = angle_ ? 1.0 : -1.0;
  pilot_.publish(rc);
}

void JoystickPlugin::stop() { close(); }

void JoystickPlugin::close() {
  if (pad_ != nullptr) SDL_GameControllerClose(pad_);
  pad_ = nullptr;
  if (sdl_up_) SDL_QuitSubSystem(SDL_INIT_GAMECONTROLLER);
  sdl_up_ = false;
}

}  // namespace tern::joystick
