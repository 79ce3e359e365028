// core/apps/console/console_commands.hpp: what the console page may ask of a flying host, and the
// description of the parameters it draws its sliders from. JSON in, JSON out; every request is
// checked here and a bad one is answered with {"type":"error","message":...}, never thrown.
//
// Requests (one JSON object per WebSocket message):
//   {"type":"param", "name":"slc.roll_kp", "value":0.6}
//       Host::request_param(name, value, "console"): the path of `tern param set`, validated
//       against the ParamSpec, applied at the next tick, recorded in params.csv with source
//       "console". Value: a number, true/false, a string, or an array of numbers.
//       Answer {"type":"param_ok","name":..,"value":..}.
//   {"type":"pilot", "manual":true, "angle":false, "roll":r, "pitch":p, "yaw":y, "throttle":t}
//       Host::set_pilot: the sticks (roll, pitch, yaw -1..1, right / nose up / nose right
//       positive; throttle 0..1) and switches a receiver reports on `rc`: manual is the override
//       switch (the controller's manual modes), angle puts aux channel 0 high (+1, else -1:
//       angle mode when the controller's angle_mode_aux is 0). No answer.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "tern/msg/sensors.hpp"

namespace tern::core {

class Host;

/// Every parameter of `host`: name, instance, kind, value, default, unit, min, max, choices,
/// size, live, description. Call between flights (reads the values).
nlohmann::json param_catalogue(const Host& host);

/// The sticks and switches of a "pilot" request. Throws std::invalid_argument naming the field
/// when a stick is missing, not a finite number or out of its range.
msg::Rc pilot_from_json(const nlohmann::json& j);

/// Answers one request from the page (see above); "" when there is nothing to answer.
std::string handle_request(Host& host, const std::string& text);

}  // namespace tern::core
