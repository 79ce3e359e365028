// The joystick adapter without a device: its parameters are checked, and start() says clearly
// that there is no controller (this machine has none; a virtual one needs /dev/uinput).
#include <doctest/doctest.h>

#include <SDL.h>

#include "joystick_plugin.hpp"
#include "tern/testing/harness.hpp"

using namespace tern;
using tern::testing::Harness;

TEST_CASE("parameters: axes, deadband and expo are range-checked") {
  Harness h(std::make_unique<joystick::JoystickPlugin>());
  CHECK_THROWS_AS(h.set_param("roll_axis", std::int64_t{6}), ParamError);
  CHECK_THROWS_AS(h.set_param("deadband", 0.6), ParamError);
  CHECK_THROWS_AS(h.set_param("expo", -0.1), ParamError);
  CHECK_NOTHROW(h.set_param("expo", 0.5));
}

TEST_CASE("no controller: start() throws a message that names what SDL sees and the console") {
  Harness h(std::make_unique<joystick::JoystickPlugin>(), {{"device", std::int64_t{15}}});
  try {
    h.start();
    FAIL("started without a controller number 15");
  } catch (const std::exception& e) {
    const std::string what = e.what();
    CHECK(what.find("no game controller number 15") != std::string::npos);
    CHECK(what.find("--console") != std::string::npos);
  }
  if (SDL_NumJoysticks() <= 0)
    MESSAGE("no joystick on this machine (and no /dev/uinput for a virtual one): the device path is not exercised here");
}
