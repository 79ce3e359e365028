// emulator/rc_script.cpp: see rc_script.hpp.
#include "rc_script.hpp"

#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

namespace tern::fcu::emulator {

namespace {
const std::map<std::string, int> kKeys = {{"roll", 0}, {"pitch", 1}, {"throttle", 2}, {"yaw", 3},  {"aux1", 4},
                                          {"aux2", 5}, {"aux3", 6},  {"aux4", 7},     {"lost", -1}};

double number(const std::string& s, const std::string& where) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != s.size() || !std::isfinite(v)) throw std::invalid_argument("--rc: " + where + ": '" + s + "' is not a number");
  return v;
}
}  // namespace

RcScript::RcScript(const std::string& text) {
  if (text == "none") {
    receiver_ = false;
    return;
  }
  std::stringstream steps(text);
  for (std::string step; std::getline(steps, step, ';');) {
    std::stringstream words(step);
    std::string t;
    if (!(words >> t)) continue;
    Step s;
    s.t = static_cast<std::int64_t>(std::llround(number(t, "step '" + step + "'") * 1e9));
    if (!steps_.empty() && s.t < steps_.back().t) throw std::invalid_argument("--rc: step '" + step + "' goes back in time");
    for (std::string kv; words >> kv;) {
      const auto eq = kv.find('=');
      const auto key = kKeys.find(kv.substr(0, eq));
      if (eq == std::string::npos || key == kKeys.end())
        throw std::invalid_argument("--rc: '" + kv + "' is not key=value with a key of roll pitch yaw throttle aux1..aux4 lost");
      const double v = number(kv.substr(eq + 1), kv);
      const double lo = key->second == 2 || key->second < 0 ? 0.0 : -1.0;
      if (v < lo || v > 1.0) throw std::invalid_argument("--rc: '" + kv + "' is outside " + (lo == 0.0 ? "0..1" : "-1..1"));
      s.set.emplace_back(key->second, v);
    }
    steps_.push_back(std::move(s));
  }
}

Transmitter RcScript::at(std::int64_t t) const {
  Transmitter x;
  for (const Step& s : steps_) {
    if (s.t > t) break;
    for (const auto& [ch, v] : s.set) {
      if (ch < 0)
        x.lost = v != 0.0;
      else
        x.value[static_cast<std::size_t>(ch)] = v;
    }
  }
  return x;
}

firmware::RcFrame RcScript::frame(const Transmitter& x) {
  firmware::RcFrame f;
  for (std::size_t i = 0; i < 8; ++i) {
    const double pwm = i == 2 ? 1000.0 + 1000.0 * x.value[i] : 1500.0 + 500.0 * x.value[i];
    f.chan[i] = static_cast<float>((std::round(pwm) - 1000.0) / 1000.0);
  }
  f.lost = x.lost;
  return f;
}

}  // namespace tern::fcu::emulator
