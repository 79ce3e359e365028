// tern/msg/control.hpp: controller commands, controller internals and actuator commands
// (topics `controller_command`, `controller_internals`, `actuators`). Mirrors ROSplane's
// ControllerCommands and ControllerInternals.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "tern/time.hpp"

namespace tern::msg {

/// What the path follower asks of the controller, topic `controller_command`.
struct ControllerCommand {
  static constexpr std::string_view type_name = "tern/ControllerCommand";
  Nanos stamp = 0;
  double Va_c = 0.0;     ///< commanded airspeed, m/s
  double h_c = 0.0;      ///< commanded altitude above the origin, m
  double chi_c = 0.0;    ///< commanded course, rad
  double phi_ff = 0.0;   ///< roll feed-forward for orbits, rad (Beard & McLain, section 10.3)
  double phi_c = 0.0;    ///< roll command used instead of the course loop when override_phi, rad
  double theta_c = 0.0;  ///< pitch command used instead of the altitude loop when override_theta, rad
  bool override_phi = false;
  bool override_theta = false;
  std::array<double, 4> aux{};  ///< auxiliary commands (ROSplane's aux)
  bool aux_valid = false;
  /// On a land item's final approach (and its flare and rollout): h_td is the touchdown point's
  /// altitude above the origin, m, in the estimate's frame; flare and rollout laws measure the
  /// height above the runway from it.
  bool landing = false;
  double h_td = 0.0;
  template <class V>
  static constexpr void describe(V& v) {
    v(&ControllerCommand::stamp, "stamp", "ns");
    v(&ControllerCommand::Va_c, "Va_c", "m/s");
    v(&ControllerCommand::h_c, "h_c", "m");
    v(&ControllerCommand::chi_c, "chi_c", "rad");
    v(&ControllerCommand::phi_ff, "phi_ff", "rad");
    v(&ControllerCommand::phi_c, "phi_c", "rad");
    v(&ControllerCommand::theta_c, "theta_c", "rad");
    v(&ControllerCommand::override_phi, "override_phi", "bool");
    v(&ControllerCommand::override_theta, "override_theta", "bool");
    v(&ControllerCommand::aux, "aux", "");
    v(&ControllerCommand::aux_valid, "aux_valid", "bool");
    v(&ControllerCommand::landing, "landing", "bool");
    v(&ControllerCommand::h_td, "h_td", "m");
  }
};

/// The controller's inner commands, topic `controller_internals`.
struct ControllerInternals {
  static constexpr std::string_view type_name = "tern/ControllerInternals";
  Nanos stamp = 0;
  double phi_c = 0.0;         ///< roll command from the course loop, rad
  double theta_c = 0.0;       ///< pitch command from the altitude (or energy) loop, rad
  double delta_t_c = 0.0;     ///< throttle command before saturation, 0..1
  std::uint8_t alt_zone = 0;  ///< flight phase in which the command was made (FlightPhase::Phase)
  template <class V>
  static constexpr void describe(V& v) {
    v(&ControllerInternals::stamp, "stamp", "ns");
    v(&ControllerInternals::phi_c, "phi_c", "rad");
    v(&ControllerInternals::theta_c, "theta_c", "rad");
    v(&ControllerInternals::delta_t_c, "delta_t_c", "");
    v(&ControllerInternals::alt_zone, "alt_zone", "enum");
  }
};

/// Surface deflections and throttle, topic `actuators`. The I/O plugin maps these to its
/// hardware (PWM, mixer, servo limits). Signs follow the uavbook (section 4.2) with its
/// derivatives: positive delta_a rolls right (C_ell_delta_a > 0), positive delta_e pitches the
/// nose down (C_m_delta_e < 0), positive delta_r yaws the nose left (C_n_delta_r < 0).
struct Actuators {
  static constexpr std::string_view type_name = "tern/Actuators";
  Nanos stamp = 0;
  double delta_a = 0.0;  ///< aileron, rad
  double delta_e = 0.0;  ///< elevator, rad
  double delta_r = 0.0;  ///< rudder, rad
  double delta_t = 0.0;  ///< throttle, 0..1
  double brake = 0.0;    ///< wheel brakes, 0 (off) .. 1 (full)
  template <class V>
  static constexpr void describe(V& v) {
    v(&Actuators::stamp, "stamp", "ns");
    v(&Actuators::delta_a, "delta_a", "rad");
    v(&Actuators::delta_e, "delta_e", "rad");
    v(&Actuators::delta_r, "delta_r", "rad");
    v(&Actuators::delta_t, "delta_t", "");
    v(&Actuators::brake, "brake", "");
  }
};

}  // namespace tern::msg
