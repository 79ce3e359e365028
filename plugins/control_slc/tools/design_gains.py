#!/usr/bin/env python3
"""Successive-loop-closure gain design for tern's control_slc / control_tecs.

Beard & McLain, *Small Unmanned Aircraft*, ch. 5 (trim, transfer functions) and ch. 6
(successive loop closure). Reads a ROSflight-style aircraft dynamics file (the format of
rosflight_sim's anaconda_dynamics.yaml / aerosonde_dynamics.yaml: every `ros__parameters`
section is merged), trims for straight and level flight at the airspeed Va, prints the
transfer-function coefficients a_phi1 a_phi2 a_theta1..3 a_V1..3 a_beta1 a_beta2 and the
gains, and with --yaml writes a flat `param: value` file loadable with `param_file:`.

Reads tern's aircraft format (configs/aircraft/*.yaml, as sim_aero and `tern aero` do; mass,
inertia and the stall_blend switch come from the file) or a ROSflight dynamics file (then give
--mass and --J, and the lift is blended as in the book).

Usage:  design_gains.py configs/aircraft/anaconda.yaml --Va 17 [--yaml out.yaml]
        design_gains.py anaconda_dynamics.yaml --Va 17 --mass 4.5 --J 0.24855 0.3784 0.618 0.06

Only the Python standard library and PyYAML are needed. The design knobs (bandwidths,
damping ratios, bandwidth separations) are command-line options; their defaults are the
values used for configs/gains/*.yaml.
"""
import argparse
import math
import sys

import yaml

G = 9.81


TERN_KEYS = {  # tern aircraft file section/key -> ROSflight name used below
    ("environment", "rho"): "rho", ("wing", "S"): "wing_s", ("wing", "b"): "wing_b",
    ("wing", "c"): "wing_c", ("wing", "M"): "wing_M", ("wing", "alpha0"): "wing_alpha0",
    ("propulsion", "D_prop"): "D_prop", ("propulsion", "K_Q"): "KQ", ("propulsion", "V_max"): "V_max",
    ("propulsion", "R_motor"): "R_motor", ("propulsion", "i0"): "I_0",
}


def load(path):
    """Returns (parameters with ROSflight names, mass or None, (Jx, Jy, Jz, Jxz) or None,
    Oswald e or None, stall_blend)."""
    with open(path) as f:
        doc = yaml.safe_load(f)
    if "wing" in doc and "aero" in doc:  # tern aircraft format
        p = {}
        for (sec, key), name in TERN_KEYS.items():
            if key in doc.get(sec, {}):
                p[name] = float(doc[sec][key])
        for key, v in doc["aero"].items():
            p[key.replace("_0", "_O") if key.endswith("_0") else key] = float(v)
        for i in range(3):
            p[f"CT_{i}"] = float(doc["propulsion"][f"C_T_{i}"])
            p[f"CQ_{i}"] = float(doc["propulsion"][f"C_Q_{i}"])
        if "KQ" not in p:
            p["KQ"] = 60.0 / (2 * math.pi * float(doc["propulsion"]["K_V"]))
        J = doc["inertia"]
        return (p, float(doc["mass"]), (J["Jx"], J["Jy"], J["Jz"], J["Jxz"]), float(doc["wing"]["e"]),
                bool(doc["wing"].get("stall_blend", True)))
    p = {}
    for node in doc.values():
        if isinstance(node, dict) and isinstance(node.get("ros__parameters"), dict):
            p.update(node["ros__parameters"])
    for key, v in p.items():  # PyYAML reads YAML 1.1: "-.99" stays a string
        if isinstance(v, str):
            try:
                p[key] = float(v)
            except ValueError:
                pass
    return p, None, None, None, True


class Aircraft:
    def __init__(self, p, mass, J, e, stall_blend=True):
        self.p = p
        self.stall_blend = stall_blend
        self.m = mass
        self.Jx, self.Jy, self.Jz, self.Jxz = J
        self.rho = p["rho"]
        self.S, self.b, self.c = p["wing_s"], p["wing_b"], p["wing_c"]
        self.AR = self.b ** 2 / self.S
        self.e = e
        Gam = self.Jx * self.Jz - self.Jxz ** 2
        self.G3, self.G4 = self.Jz / Gam, self.Jxz / Gam

    def CL(self, a):  # uavbook eq. 4.9 (blended lift); sigma ~ 0 at small alpha
        p = self.p
        if not self.stall_blend:
            return p["C_L_O"] + p["C_L_alpha"] * a
        M, a0 = p["wing_M"], p["wing_alpha0"]
        e1, e2 = math.exp(-M * (a - a0)), math.exp(M * (a + a0))
        sig = (1 + e1 + e2) / ((1 + e1) * (1 + e2))
        lin = p["C_L_O"] + p["C_L_alpha"] * a
        return (1 - sig) * lin + sig * 2 * math.copysign(1, a) * math.sin(a) ** 2 * math.cos(a)

    def CD(self, a):  # drag polar
        p = self.p
        return p["C_D_p"] + (p["C_L_O"] + p["C_L_alpha"] * a) ** 2 / (math.pi * self.e * self.AR)

    def thrust(self, Va, dt):  # propulsion supplement (motor + propeller)
        p, rho = self.p, self.rho
        D = p["D_prop"]
        V_in = p["V_max"] * dt
        a = rho * D ** 5 * p["CQ_0"] / (2 * math.pi) ** 2
        b = rho * D ** 4 * p["CQ_1"] * Va / (2 * math.pi) + p["KQ"] ** 2 / p["R_motor"]
        c = rho * D ** 3 * p["CQ_2"] * Va ** 2 - p["KQ"] * V_in / p["R_motor"] + p["KQ"] * p["I_0"]
        Om = (-b + math.sqrt(max(b * b - 4 * a * c, 0.0))) / (2 * a)
        J = 2 * math.pi * Va / (Om * D)
        CT = p["CT_2"] * J ** 2 + p["CT_1"] * J + p["CT_0"]
        return rho * (Om / (2 * math.pi)) ** 2 * D ** 4 * CT

    def trim_level(self, Va):
        """Straight and level trim: theta = alpha, C_m = 0, Z = 0, X = 0. Returns alpha, de, dt."""
        p = self.p
        qS = 0.5 * self.rho * Va ** 2 * self.S

        def de_of(a):
            return -(p["C_m_O"] + p["C_m_alpha"] * a) / p["C_m_delta_e"]

        def z(a):  # body-z force with theta = alpha (level flight)
            de = de_of(a)
            L = qS * (self.CL(a) + p["C_L_delta_e"] * de)
            D = qS * (self.CD(a) + p["C_D_delta_e"] * de)
            return -math.sin(a) * D - math.cos(a) * L + self.m * G * math.cos(a)

        # the first sign change of Z from alpha = -0.2 upward (the attached-flow branch)
        lo = -0.2
        while z(lo + 0.005) > 0 and lo < 0.5:
            lo += 0.005
        if lo >= 0.5:
            raise SystemExit(f"no level-flight trim found at Va = {Va} m/s")
        hi = lo + 0.005
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if (z(lo) > 0) == (z(mid) > 0):
                lo = mid
            else:
                hi = mid
        a = 0.5 * (lo + hi)
        de = de_of(a)
        L = qS * (self.CL(a) + p["C_L_delta_e"] * de)
        D = qS * (self.CD(a) + p["C_D_delta_e"] * de)
        T_req = self.m * G * math.sin(a) + math.cos(a) * D - math.sin(a) * L
        lo, hi = 0.0, 1.0
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if self.thrust(Va, mid) < T_req:
                lo = mid
            else:
                hi = mid
        return a, de, 0.5 * (lo + hi)

    def coefficients(self, Va):
        """Transfer-function coefficients, uavbook sections 5.4 (eqs. 5.23-5.29 and the
        propulsion-model form of a_V1, a_V2)."""
        p, rho, S, b, c = self.p, self.rho, self.S, self.b, self.c
        a, de, dt = self.trim_level(Va)
        Cpp = self.G3 * p["C_ell_p"] + self.G4 * p["C_n_p"]
        Cpda = self.G3 * p["C_ell_delta_a"] + self.G4 * p["C_n_delta_a"]
        k = {}
        k["alpha_trim"], k["delta_e_trim"], k["delta_t_trim"] = a, de, dt
        k["a_phi1"] = -0.25 * rho * Va * S * b ** 2 * Cpp
        k["a_phi2"] = 0.5 * rho * Va ** 2 * S * b * Cpda
        qc = rho * Va ** 2 * c * S / (2 * self.Jy)
        k["a_theta1"] = -qc * p["C_m_q"] * c / (2 * Va)
        k["a_theta2"] = -qc * p["C_m_alpha"]
        k["a_theta3"] = qc * p["C_m_delta_e"]
        h = 1e-4
        dT_dVa = (self.thrust(Va + h, dt) - self.thrust(Va - h, dt)) / (2 * h)
        dT_ddt = (self.thrust(Va, dt + h) - self.thrust(Va, dt - h)) / (2 * h)
        k["a_V1"] = rho * Va * S / self.m * (self.CD(a) + p["C_D_delta_e"] * de) - dT_dVa / self.m
        k["a_V2"] = dT_ddt / self.m
        k["a_V3"] = G  # g cos(theta* - alpha*), level trim
        k["a_beta1"] = -rho * Va * S / (2 * self.m) * p["C_Y_beta"]
        k["a_beta2"] = rho * Va * S / (2 * self.m) * p["C_Y_delta_r"]
        return k


def design(k, Va, o):
    """uavbook section 6.1 (lateral) and 6.2 (longitudinal) successive loop closure.
    tern's pitch gains are magnitudes: delta_e = trim_e - (kp (theta_c - theta) - kd q), so
    pitch_kp = -k_p_theta and pitch_kd = -k_d_theta of the book (a_theta3 < 0)."""
    g = {}
    # roll: phi/delta_a = a_phi2 / (s (s + a_phi1)); closed loop s^2 + (a_phi1 + a_phi2 kd) s + a_phi2 kp.
    # Default natural frequency: a_phi1 / (2 zeta), the fastest loop with damping zeta that needs
    # no rate feedback (kd = 0); a larger --wn-phi adds kd.
    wn_phi = o.wn_phi if o.wn_phi is not None else k["a_phi1"] / (2 * o.zeta_phi)
    g["roll_kp"] = wn_phi ** 2 / k["a_phi2"]
    g["roll_kd"] = max(0.0, (2 * o.zeta_phi * wn_phi - k["a_phi1"]) / k["a_phi2"])
    g["roll_ki"] = 0.0
    # roll command shaping (tern): the roll loop is type 0 in phi, so a roll command ramping at
    # p_c is followed with a lag of p_c a_phi1 / (a_phi2 kp) (0.1 s on the Anaconda: 10 deg behind
    # a 90 deg/s ramp) unless the aileron that sustains p_c, a_phi1 / a_phi2 p_c (the steady state
    # of phi'' = -a_phi1 phi' + a_phi2 delta_a), is fed forward; the controller slew-limits the
    # command to --roll-rate-max (about 40 % of the full-aileron roll rate a_phi2 max_a / a_phi1)
    # so that the feed-forward keeps most of the aileron travel for the feedback.
    g["roll_ff"] = k["a_phi1"] / k["a_phi2"]
    g["roll_rate_max"] = o.roll_rate_max
    # the slow pole of the roll loop (kd may be clamped at 0 when a_phi1 is large)
    s1 = k["a_phi1"] + k["a_phi2"] * g["roll_kd"]
    s0 = k["a_phi2"] * g["roll_kp"]
    disc = s1 * s1 - 4 * s0
    w_roll = (s1 - math.sqrt(disc)) / 2 if disc > 0 else math.sqrt(s0)
    # course: chi/phi = (g/Vg)/s (section 6.1.2). P bandwidth wc = wn_phi / W_chi (course_kp = wc Vg/g)
    # and an integrator with reset time T_chi (course_ki = course_kp / T_chi): the book's PI with a
    # large damping ratio. A slow integrator trims steady roll biases; a fast one overshoots at
    # the path follower's line -> orbit transitions (measured on the hourglass mission).
    # The model chi/phi = (g/Vg)/s is the coordinated turn at Va; in flight the heading lags the
    # roll (sideslip, the yaw damper before its washout, the estimator) and the loop gain grows in
    # a turn (d(tan phi)/d phi = 1/cos^2 phi). With W_chi = 5.5 the Anaconda's course loop
    # oscillated in the hourglass's downwind turns (+-3..6 deg course, roll command swinging
    # 20-45 deg, period 1.4-1.7 s, which also stirred the pitch loop), so the default is
    # W_chi = 10, the book's upper end (configs/gains/README.md); `tern aero gains` designs the same.
    wc = math.sqrt(s0) / o.W_chi
    g["course_kp"] = wc * Va / G
    g["course_ki"] = g["course_kp"] / o.T_chi
    g["course_kd"] = 0.0
    # pitch: theta/delta_e = a_theta3 / (s^2 + a_theta1 s + a_theta2)
    # choose the closed-loop DC gain K_theta_DC: kp a3 / (a2 + kp a3) = K  ->  kp = K a2 / ((1 - K) a3)
    kp_th = o.K_theta_DC * k["a_theta2"] / ((1 - o.K_theta_DC) * k["a_theta3"])
    wn_th = math.sqrt(k["a_theta2"] + kp_th * k["a_theta3"])
    kd_th = (2 * o.zeta_theta * wn_th - k["a_theta1"]) / k["a_theta3"]
    K_dc = kp_th * k["a_theta3"] / (k["a_theta2"] + kp_th * k["a_theta3"])
    # a small integrator (zero a decade below wn_theta times --pitch-ki-ratio) removes the pitch
    # loop's steady error (1 - K_theta_DC) without changing the altitude design
    g["pitch_kp"], g["pitch_kd"] = -kp_th, max(0.0, -kd_th)
    g["pitch_ki"] = o.pitch_ki_ratio * (-kp_th) * wn_th
    # altitude: h/theta = Va/s through the pitch loop's DC gain K_theta_DC (eq. 6.24)
    wn_h = wn_th / o.W_h
    g["altitude_ki"] = wn_h ** 2 / (K_dc * Va)
    g["altitude_kp"] = 2 * o.zeta_h * wn_h / (K_dc * Va)
    g["altitude_kd"] = 0.0
    # airspeed with throttle: Va/delta_t = a_V2 / (s + a_V1) (eq. 6.29)
    wn_v = o.wn_V
    g["airspeed_ki"] = wn_v ** 2 / k["a_V2"]
    g["airspeed_kp"] = max(0.0, (2 * o.zeta_V * wn_v - k["a_V1"]) / k["a_V2"])
    g["airspeed_kd"] = 0.0
    # yaw damper (section 6.1.3, washout on r)
    g["yaw_damper_kr"] = o.kr
    g["yaw_damper_p_wo"] = o.p_wo
    g["trim_e"] = k["delta_e_trim"]
    g["trim_t"] = k["delta_t_trim"]
    return g, K_dc, w_roll


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dynamics")
    ap.add_argument("--Va", type=float, required=True, help="trim airspeed, m/s")
    ap.add_argument("--mass", type=float, help="kg (ROSflight files only)")
    ap.add_argument("--J", type=float, nargs=4, metavar=("Jx", "Jy", "Jz", "Jxz"), help="kg m^2 (ROSflight files only)")
    ap.add_argument("--e", type=float, help="Oswald efficiency (default: the file's, else 0.9)")
    ap.add_argument("--wn-phi", dest="wn_phi", type=float, help="roll natural frequency, rad/s (default a_phi1/(2 zeta_phi))")
    ap.add_argument("--zeta-phi", dest="zeta_phi", type=float, default=0.8)
    ap.add_argument("--W-chi", dest="W_chi", type=float, default=10.0, help="roll/course bandwidth separation")
    ap.add_argument("--roll-rate-max", dest="roll_rate_max", type=float, default=1.5,
                    help="slew limit of the roll command, rad/s (about 0.4 a_phi2 max_a / a_phi1)")
    ap.add_argument("--T-chi", dest="T_chi", type=float, default=25.0, help="course integrator reset time, s")
    ap.add_argument("--K-theta-DC", dest="K_theta_DC", type=float, default=0.7, help="pitch loop DC gain (sets pitch_kp)")
    ap.add_argument("--pitch-ki-ratio", dest="pitch_ki_ratio", type=float, default=0.1,
                    help="pitch_ki = ratio * pitch_kp * wn_theta (0: no pitch integrator)")
    ap.add_argument("--zeta-theta", dest="zeta_theta", type=float, default=0.8)
    ap.add_argument("--W-h", dest="W_h", type=float, default=25.0, help="altitude/pitch bandwidth separation")
    ap.add_argument("--zeta-h", dest="zeta_h", type=float, default=1.0)
    ap.add_argument("--wn-V", dest="wn_V", type=float, default=1.5, help="airspeed natural frequency, rad/s")
    ap.add_argument("--zeta-V", dest="zeta_V", type=float, default=1.0)
    ap.add_argument("--kr", type=float, default=0.3, help="yaw damper gain, rad rudder per rad/s")
    ap.add_argument("--p-wo", dest="p_wo", type=float, default=0.5, help="washout pole, rad/s")
    ap.add_argument("--yaml", help="write the gains as a flat param file")
    o = ap.parse_args(argv)
    p, mass, J, e, blend = load(o.dynamics)
    mass = o.mass if o.mass is not None else mass
    J = o.J if o.J is not None else J
    e = o.e if o.e is not None else (e if e is not None else 0.9)
    if mass is None or J is None:
        ap.error("a ROSflight dynamics file needs --mass and --J")
    ac = Aircraft(p, mass, J, e, blend)
    k = ac.coefficients(o.Va)
    g, K_dc, w_roll = design(k, o.Va, o)
    print(f"# trim at Va = {o.Va} m/s: alpha = {k['alpha_trim']:.4f} rad, delta_e = {k['delta_e_trim']:.4f} rad, "
          f"delta_t = {k['delta_t_trim']:.4f}")
    for name in ["a_phi1", "a_phi2", "a_theta1", "a_theta2", "a_theta3", "a_V1", "a_V2", "a_V3", "a_beta1", "a_beta2"]:
        print(f"#   {name} = {k[name]:.4f}")
    print(f"#   full-aileron roll rate per rad of aileron a_phi2/a_phi1 = {k['a_phi2'] / k['a_phi1']:.3f} rad/s")
    print(f"#   roll_ff = a_phi1/a_phi2 feeds the rate of the roll command forward to the aileron; roll_rate_max =")
    print(f"#     {o.roll_rate_max:g} rad/s slew-limits that command (added for the tracking benchmark; design_gains.py).")
    print(f"#   roll loop wn {math.sqrt(k['a_phi2'] * g['roll_kp']):.3f} rad/s, slowest pole {w_roll:.3f} rad/s, "
          f"course loop bandwidth {math.sqrt(k['a_phi2'] * g['roll_kp']) / o.W_chi:.3f} rad/s, K_theta_DC = {K_dc:.4f}, "
          f"pitch loop wn = {math.sqrt(k['a_theta2'] - g['pitch_kp'] * k['a_theta3']):.3f} rad/s")
    lines = [f"{n}: {v:.6g}" for n, v in g.items()]
    print("\n".join(lines))
    if o.yaml:
        with open(o.yaml, "w") as f:
            f.write("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
