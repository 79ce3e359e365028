#include "joystick_plugin.hpp"
TERN_PLUGIN(tern::joystick::JoystickPlugin, "joystick", tern::PluginKind::io,
            "a game controller or RC transmitter in joystick mode (SDL2) as the pilot: sticks and switches on topic pilot");
