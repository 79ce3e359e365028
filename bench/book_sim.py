#!/usr/bin/python3
"""book_sim.py: an independent fixed-wing simulator that writes a tern sensor log (docs/sensor-log.md).

Written from Beard & McLain, *Small Unmanned Aircraft: Theory and Practice* (the "uavbook", 2nd ed.),
not from tern's simulator, so that `tern sysid` / `tern validate` meet a flight they did not write:
  * ch. 3: 6-DOF rigid body, Euler-angle kinematics (eqs. 3.14-3.17, the Gamma terms of the inertia);
  * ch. 4.2: longitudinal and lateral aerodynamics, lift with the sigmoid stall blend (M, alpha0;
    off where the file says stall_blend: false), the drag polar
    C_D = C_D_p + (C_L_0 + C_L_alpha alpha)^2/(pi e AR) + C_D_q c q/(2 Va) + C_D_delta_e delta_e;
  * ch. 4.3: propulsion: a DC motor driving a propeller with C_T(J), C_Q(J) quadratics, the motor
    speed from the torque balance (a quadratic in Omega), the propeller's torque -Q_p on the airframe;
  * ch. 4.4: wind: a steady NED wind plus Dryden gusts (light turbulence at low altitude) in body axes;
  * ch. 5: trim (straight and level) and the transfer functions' coefficients (a_phi, a_theta, a_V);
  * ch. 6: successive loop closure: roll (phi, p), course (chi), pitch (theta, q), altitude (h) through
    pitch, airspeed through throttle, a washed-out yaw-rate damper on the rudder;
  * ch. 7: sensors: rate gyros and accelerometers (noise, constant bias), barometer (ISA static
    pressure), pitot differential pressure, magnetometer, GNSS with Gauss-Markov position error;
  * ch. 8.3: the altitude the autopilot holds is the low-passed barometric altitude.
The autopilot's attitude and course are the truth at the sample (a stand-in for an onboard estimator,
as the book's ch. 6 assumes known states); rates come from the gyro, airspeed from the pitot.
On top of the autopilot: an identification schedule (Klein & Morelli ch. 9 style: 3-2-1-1, doublets,
chirps, one axis at a time) at three airspeeds with course changes.
Signs: the book's (positive delta_e pitches nose down, positive delta_r yaws nose left).

  book_sim.py --aircraft configs/aircraft/aerosonde.yaml --out DIR [--seed N] [--duration 300]
              [--imu-rate 200] [--cmd-rate 50] [--cmd-delay-samples 1] [--turbulence light|none]
              [--wind N E] [--excitation-table] [--pitot body-x|full] [--speeds 20 25 30]
Writes DIR/sensor_log.yaml, DIR/topics/{imu,gnss,baro,diff_pressure,mag,actuators,reference}.csv,
(--excitation-table) DIR/topics/excitation.csv, and DIR/book_truth.csv.
"""
import argparse
import math
import os
import sys
import time

import numpy as np
import yaml

import sdk_constants

G = sdk_constants.constant("math.hpp", "kGravity")  # the book's g
ORIGIN = (47.3977, 8.5456, 488.0)            # lat deg, lon deg, alt m (ground level)
MAG_NED = (2.151e-5, 0.130e-5, 4.323e-5)    # T: WMM-2025 at the origin on 2025-06-01 (D 3.47, I 63.51 deg)
D2R = sdk_constants.constant("math.hpp", "kPi") / 180.0  # tern/math.hpp's kRadPerDeg
# the ISA's barometric formula p = p0 (1 - k h)^n (tern/atmosphere.hpp)
P0 = sdk_constants.constant("atmosphere.hpp", "kIsaSeaLevelPressure")
ISA_K = sdk_constants.constant("atmosphere.hpp", "kIsaPressureLapse")
ISA_N = sdk_constants.constant("atmosphere.hpp", "kIsaPressureExponent")


# ----------------------------------------------------------------------------------------------
# The aircraft
# ----------------------------------------------------------------------------------------------
def load_aircraft(path):
    """The aircraft file flattened into one dict of the book's symbols, plus the Gamma terms."""
    with open(path) as f:
        d = yaml.safe_load(f)
    P = {"name": d.get("name", os.path.basename(path)), "mass": float(d["mass"])}
    for sec in ("inertia", "environment", "wing", "aero", "propulsion", "servos"):
        P.update({k: v for k, v in (d.get(sec) or {}).items()})
    P.setdefault("stall_blend", True)
    P.setdefault("tau", 0.0)
    for k in ("max_delta_a", "max_delta_e", "max_delta_r"):
        P.setdefault(k, 45.0 * D2R)
    if "K_Q" not in P:
        P["K_Q"] = 60.0 / (2.0 * math.pi * P["K_V"])     # N m/A (= back-EMF constant, V s/rad)
    P["K_V_si"] = P["K_Q"]
    P["AR"] = P["b"] ** 2 / P["S"]
    Jx, Jy, Jz, Jxz = P["Jx"], P["Jy"], P["Jz"], P["Jxz"]
    g = Jx * Jz - Jxz ** 2
    P["Gam"] = (None, Jxz * (Jx - Jy + Jz) / g, (Jz * (Jz - Jy) + Jxz ** 2) / g, Jz / g, Jxz / g,
                (Jz - Jx) / Jy, Jxz / Jy, ((Jx - Jy) * Jx + Jxz ** 2) / g, Jx / g)
    return P


# ----------------------------------------------------------------------------------------------
# Forces and moments (ch. 4)
# ----------------------------------------------------------------------------------------------
def lift_drag_alpha(P, alpha):
    """C_L(alpha) with the book's blend (eq. 4.9-4.10) and the polar's C_D(alpha) (eq. 4.11)."""
    lin = P["C_L_0"] + P["C_L_alpha"] * alpha
    cl = lin
    if P["stall_blend"]:
        M, a0 = P["M"], P["alpha0"]
        e1 = math.exp(min(-M * (alpha - a0), 50.0))
        e2 = math.exp(min(M * (alpha + a0), 50.0))
        sig = (1.0 + e1 + e2) / ((1.0 + e1) * (1.0 + e2))
        flat = 2.0 * math.copysign(1.0, alpha) * math.sin(alpha) ** 2 * math.cos(alpha)
        cl = (1.0 - sig) * lin + sig * flat
    cd = P["C_D_p"] + lin * lin / (math.pi * P["e"] * P["AR"])
    return cl, cd


def propeller(P, Va, delta_t):
    """Thrust and torque of the motor-propeller pair (sec. 4.3): Omega from the torque balance."""
    rho, D = P["rho"], P["D_prop"]
    KQ, KV, R = P["K_Q"], P["K_V_si"], P["R_motor"]
    v_in = P["V_max"] * delta_t
    a = rho * D ** 5 * P["C_Q_0"] / (2.0 * math.pi) ** 2
    b = rho * D ** 4 * P["C_Q_1"] * Va / (2.0 * math.pi) + KQ * KV / R
    c = rho * D ** 3 * P["C_Q_2"] * Va * Va - KQ * v_in / R + KQ * P["i0"]
    omega = (-b + math.sqrt(max(b * b - 4.0 * a * c, 0.0))) / (2.0 * a)
    omega = max(omega, 1e-3)
    J = 2.0 * math.pi * Va / (omega * D)
    ct = P["C_T_2"] * J * J + P["C_T_1"] * J + P["C_T_0"]
    cq = P["C_Q_2"] * J * J + P["C_Q_1"] * J + P["C_Q_0"]
    n2 = (omega / (2.0 * math.pi)) ** 2
    return rho * n2 * D ** 4 * ct, rho * n2 * D ** 5 * cq


def air_data(x, wind_b):
    """Body-frame airspeed components, Va, alpha, beta (sec. 2.3, 4.4)."""
    ur, vr, wr = x[3] - wind_b[0], x[4] - wind_b[1], x[5] - wind_b[2]
    Va = math.sqrt(ur * ur + vr * vr + wr * wr)
    alpha = math.atan2(wr, ur)
    beta = math.asin(max(-1.0, min(1.0, vr / Va))) if Va > 1e-6 else 0.0
    return ur, vr, wr, Va, alpha, beta


def forces_moments(P, x, wind_b, da, de, dr, dt):
    """Aerodynamic + propulsive forces (body, N, no gravity) and moments (N m), and the air data."""
    ur, vr, wr, Va, alpha, beta = air_data(x, wind_b)
    p, q, r = x[9], x[10], x[11]
    qbar = 0.5 * P["rho"] * Va * Va
    S, b, c = P["S"], P["b"], P["c"]
    cq_, bp, br = c * q / (2 * Va), b * p / (2 * Va), b * r / (2 * Va)
    cla, cda = lift_drag_alpha(P, alpha)
    CL = cla + P["C_L_q"] * cq_ + P["C_L_delta_e"] * de
    CD = cda + P["C_D_q"] * cq_ + P["C_D_delta_e"] * de
    ca, sa = math.cos(alpha), math.sin(alpha)
    lift, drag = qbar * S * CL, qbar * S * CD
    fx = -ca * drag + sa * lift
    fz = -sa * drag - ca * lift
    fy = qbar * S * (P["C_Y_0"] + P["C_Y_beta"] * beta + P["C_Y_p"] * bp + P["C_Y_r"] * br
                     + P["C_Y_delta_a"] * da + P["C_Y_delta_r"] * dr)
    l = qbar * S * b * (P["C_ell_0"] + P["C_ell_beta"] * beta + P["C_ell_p"] * bp + P["C_ell_r"] * br
                        + P["C_ell_delta_a"] * da + P["C_ell_delta_r"] * dr)
    m = qbar * S * c * (P["C_m_0"] + P["C_m_alpha"] * alpha + P["C_m_q"] * cq_ + P["C_m_delta_e"] * de)
    n = qbar * S * b * (P["C_n_0"] + P["C_n_beta"] * beta + P["C_n_p"] * bp + P["C_n_r"] * br
                        + P["C_n_delta_a"] * da + P["C_n_delta_r"] * dr)
    thrust, torque = propeller(P, Va, dt)
    return (fx + thrust, fy, fz, l - torque, m, n), (Va, alpha, beta, ur)


# ----------------------------------------------------------------------------------------------
# Kinematics and dynamics (ch. 3), integration
# ----------------------------------------------------------------------------------------------
def rot_body_to_ned(phi, theta, psi):
    """R_b^v, body to vehicle (NED) frame (sec. 2.2, used in eq. 3.14), as row tuples."""
    cf, sf, ct, st, cp, sp = (math.cos(phi), math.sin(phi), math.cos(theta), math.sin(theta),
                              math.cos(psi), math.sin(psi))
    return ((ct * cp, sf * st * cp - cf * sp, cf * st * cp + sf * sp),
            (ct * sp, sf * st * sp + cf * cp, cf * st * sp - sf * cp),
            (-st, sf * ct, cf * ct))


def mul(R, v):
    return (R[0][0] * v[0] + R[0][1] * v[1] + R[0][2] * v[2],
            R[1][0] * v[0] + R[1][1] * v[1] + R[1][2] * v[2],
            R[2][0] * v[0] + R[2][1] * v[1] + R[2][2] * v[2])


def mul_t(R, v):
    return (R[0][0] * v[0] + R[1][0] * v[1] + R[2][0] * v[2],
            R[0][1] * v[0] + R[1][1] * v[1] + R[2][1] * v[2],
            R[0][2] * v[0] + R[1][2] * v[1] + R[2][2] * v[2])


def wind_body(x, wind_ned, gust_b):
    R = rot_body_to_ned(x[6], x[7], x[8])
    w = mul_t(R, wind_ned)
    return (w[0] + gust_b[0], w[1] + gust_b[1], w[2] + gust_b[2])


def derivatives(P, x, wind_ned, gust_b, cmd):
    """dx/dt of x = (pn pe pd u v w phi theta psi p q r da de dr): eqs. 3.14-3.17 + servo lag."""
    phi, theta, psi = x[6], x[7], x[8]
    u, v, w, p, q, r = x[3], x[4], x[5], x[9], x[10], x[11]
    R = rot_body_to_ned(phi, theta, psi)
    wb = mul_t(R, wind_ned)
    wb = (wb[0] + gust_b[0], wb[1] + gust_b[1], wb[2] + gust_b[2])
    (fx, fy, fz, l, m, n), _ = forces_moments(P, x, wb, x[12], x[13], x[14], cmd[3])
    mass, Gm = P["mass"], P["Gam"]
    cf, sf, ct, st = math.cos(phi), math.sin(phi), math.cos(theta), math.sin(theta)
    pos = mul(R, (u, v, w))
    du = r * v - q * w + fx / mass - G * st
    dv = p * w - r * u + fy / mass + G * ct * sf
    dw = q * u - p * v + fz / mass + G * ct * cf
    dphi = p + sf * st / ct * q + cf * st / ct * r
    dtheta = cf * q - sf * r
    dpsi = (sf * q + cf * r) / ct
    dp = Gm[1] * p * q - Gm[2] * q * r + Gm[3] * l + Gm[4] * n
    dq = Gm[5] * p * r - Gm[6] * (p * p - r * r) + m / P["Jy"]
    dr_ = Gm[7] * p * q - Gm[1] * q * r + Gm[4] * l + Gm[8] * n
    tau = P["tau"]
    if tau > 0:
        ds = ((cmd[0] - x[12]) / tau, (cmd[1] - x[13]) / tau, (cmd[2] - x[14]) / tau)
    else:
        ds = (0.0, 0.0, 0.0)
    return (pos[0], pos[1], pos[2], du, dv, dw, dphi, dtheta, dpsi, dp, dq, dr_) + ds


def rk4(P, x, h, wind_ned, gust_b, cmd):
    def add(a, k, s):
        return tuple(ai + s * ki for ai, ki in zip(a, k))
    k1 = derivatives(P, x, wind_ned, gust_b, cmd)
    k2 = derivatives(P, add(x, k1, h / 2), wind_ned, gust_b, cmd)
    k3 = derivatives(P, add(x, k2, h / 2), wind_ned, gust_b, cmd)
    k4 = derivatives(P, add(x, k3, h), wind_ned, gust_b, cmd)
    x = tuple(xi + h / 6 * (a + 2 * b + 2 * c + d) for xi, a, b, c, d in zip(x, k1, k2, k3, k4))
    if P["tau"] <= 0:
        x = x[:12] + tuple(cmd[:3])
    return x


# ----------------------------------------------------------------------------------------------
# Dryden gusts (sec. 4.4)
# ----------------------------------------------------------------------------------------------
class Dryden:
    """H_u = s_u sqrt(2Va/(pi L_u)) / (s + Va/L_u); H_v, H_w = s sqrt(3Va/(pi L)) (s + Va/(sqrt3 L)) /
    (s + Va/L)^2, driven by white noise of intensity pi (so that each output's variance is sigma^2,
    the MIL-F-8785C convention the book's table quotes); Euler-Maruyama at the integration step."""

    def __init__(self, rng, dt, sigma=(1.06, 1.06, 0.7), L=(200.0, 200.0, 50.0), on=True):
        self.rng, self.dt, self.sigma, self.L, self.on = rng, dt, sigma, L, on
        self.xu = 0.0
        self.xv = [0.0, 0.0]
        self.xw = [0.0, 0.0]
        self.gust = (0.0, 0.0, 0.0)

    def step(self, Va):
        if not self.on:
            return self.gust
        Va = max(Va, 10.0)
        dt = self.dt
        n = self.rng.standard_normal(3) * math.sqrt(math.pi / dt)
        (su, sv, sw), (Lu, Lv, Lw) = self.sigma, self.L
        au = Va / Lu
        self.xu += dt * (-au * self.xu + n[0])
        gu = su * math.sqrt(2 * Va / (math.pi * Lu)) * self.xu
        gv = self._second(self.xv, sv, Lv, Va, n[1])
        gw = self._second(self.xw, sw, Lw, Va, n[2])
        self.gust = (gu, gv, gw)
        return self.gust

    def _second(self, s, sigma, L, Va, noise):
        a = Va / L
        x1, x2 = s
        s[0] = x1 + self.dt * x2
        s[1] = x2 + self.dt * (-a * a * x1 - 2 * a * x2 + noise)
        return sigma * math.sqrt(3 * Va / (math.pi * L)) * (a / math.sqrt(3.0) * s[0] + s[1])


# ----------------------------------------------------------------------------------------------
# Trim (ch. 5)
# ----------------------------------------------------------------------------------------------
def trim_state(P, Va, alpha, beta):
    """The straight-and-level state (no wind, phi = 0, gamma = 0) at Va, alpha, beta."""
    u = Va * math.cos(alpha) * math.cos(beta)
    v = Va * math.sin(beta)
    w = Va * math.sin(alpha) * math.cos(beta)
    return (0.0, 0.0, 0.0, u, v, w, 0.0, alpha, 0.0, 0.0, 0.0, 0.0)


def trim(P, Va):
    """Solve alpha, beta, delta_e, delta_t, delta_a, delta_r for zero forces and moments (Newton)."""
    def resid(z):
        a, b, de, dt, da, dr = z
        x = trim_state(P, Va, a, b) + (da, de, dr)
        d = derivatives(P, x, (0, 0, 0), (0, 0, 0), (da, de, dr, dt))
        return np.array([d[3], d[4], d[5], d[9], d[10], d[11]])
    z = np.array([0.05, 0.0, -0.05, 0.5, 0.0, 0.0])
    for _ in range(50):
        f = resid(z)
        if np.max(np.abs(f)) < 1e-10:
            break
        Jm = np.empty((6, 6))
        for j in range(6):
            dz = np.zeros(6)
            dz[j] = 1e-6
            Jm[:, j] = (resid(z + dz) - f) / 1e-6
        z = z - np.linalg.solve(Jm, f)
    if np.max(np.abs(resid(z))) > 1e-6 or not 0.0 <= z[3] <= 1.0:
        raise SystemExit(f"book_sim: {P['name']} has no straight-and-level trim at {Va:g} m/s (alpha, beta, "
                         f"delta_e, delta_t, delta_a, delta_r = {np.round(z, 4).tolist()}): give --speeds "
                         "it can hold")
    return dict(zip(("alpha", "beta", "de", "dt", "da", "dr"), z.tolist()))


# ----------------------------------------------------------------------------------------------
# Autopilot design (ch. 5 transfer functions, ch. 6 successive loop closure)
# ----------------------------------------------------------------------------------------------
def design_lateral(P, Va, k):
    """Roll (k_p_phi, k_d_phi), course (k_p_chi, k_i_chi) and the yaw damper's k_r (sec. 6.3)."""
    rho, S, b, Gm = P["rho"], P["S"], P["b"], P["Gam"]
    Cpp = Gm[3] * P["C_ell_p"] + Gm[4] * P["C_n_p"]
    Cpda = Gm[3] * P["C_ell_delta_a"] + Gm[4] * P["C_n_delta_a"]
    a_phi1 = -0.5 * rho * Va ** 2 * S * b * Cpp * b / (2 * Va)
    a_phi2 = 0.5 * rho * Va ** 2 * S * b * Cpda
    k["kp_phi"] = (30 * D2R) / (15 * D2R) * math.copysign(1.0, a_phi2)     # delta_a_max / e_phi_max
    wn_phi = math.sqrt(abs(a_phi2) * abs(k["kp_phi"]))
    zeta_phi = 1.0
    k["kd_phi"] = max((2 * zeta_phi * wn_phi - a_phi1) / a_phi2, 0.02 * math.copysign(1.0, a_phi2))
    wn_chi = wn_phi / 25.0                                                   # bandwidth separation W_chi
    k["kp_chi"] = 2 * 0.8 * wn_chi * Va / G
    k["ki_chi"] = wn_chi ** 2 * Va / G
    k["wn_phi"], k["a_phi1"], k["a_phi2"] = wn_phi, a_phi1, a_phi2
    # yaw damper: the Dutch roll's (v, r) model of sec. 5.5, r fed back to the rudder
    Crb = Gm[4] * P["C_ell_beta"] + Gm[8] * P["C_n_beta"]
    Crr = Gm[4] * P["C_ell_r"] + Gm[8] * P["C_n_r"]
    Crdr = Gm[4] * P["C_ell_delta_r"] + Gm[8] * P["C_n_delta_r"]
    m = P["mass"]
    A = np.array([[rho * S * Va * P["C_Y_beta"] / (2 * m), -Va + rho * Va * S * b * P["C_Y_r"] / (4 * m)],
                  [rho * S * b * Va * Crb / 2, rho * Va * S * b * b * Crr / 4]])
    B = np.array([rho * Va ** 2 * S * P["C_Y_delta_r"] / (2 * m), rho * Va ** 2 * S * b * Crdr / 2])
    sgn = -math.copysign(1.0, B[1])                      # delta_r = sgn k_r r: a yawing moment against r
    best = (0.0, 0.0)
    for kr in np.linspace(0.0, 1.5, 301):
        ev = np.linalg.eigvals(A + np.outer(B, [0.0, sgn * kr]))
        zeta = min(-e.real / abs(e) for e in ev if abs(e) > 1e-9)
        if zeta > best[1] + 1e-6:
            best = (kr, zeta)
        if zeta >= 0.7:
            break
    k["kr"] = sgn * best[0]
    k["zeta_dr"] = best[1]
    k["p_wo"] = 0.5                                       # rad/s, washout below the Dutch roll


def design_longitudinal(P, Va, tr, k):
    """Pitch (k_p_theta, k_d_theta), altitude from pitch, airspeed from throttle (sec. 6.4)."""
    rho, S, c, Jy, m = P["rho"], P["S"], P["c"], P["Jy"], P["mass"]
    f = rho * Va ** 2 * c * S / (2 * Jy)
    a1 = -f * P["C_m_q"] * c / (2 * Va)
    a2 = -f * P["C_m_alpha"]
    a3 = f * P["C_m_delta_e"]
    kp = (30 * D2R) / (15 * D2R) * math.copysign(1.0, a3)
    wn = math.sqrt(a2 + abs(kp * a3))
    k["kp_theta"] = kp
    k["kd_theta"] = (2 * 0.7 * wn - a1) / a3
    K_dc = kp * a3 / (a2 + kp * a3)
    wn_h = wn / 30.0                                                         # W_h
    k["kp_h"] = 2 * 0.8 * wn_h / (K_dc * Va)
    k["ki_h"] = wn_h ** 2 / (K_dc * Va)
    k["wn_theta"], k["K_theta_dc"] = wn, K_dc
    # airspeed through throttle: a_V1, a_V2 by differences of the model at trim
    _, cd = lift_drag_alpha(P, tr["alpha"])
    cd += P["C_D_delta_e"] * tr["de"]
    T0, _ = propeller(P, Va, tr["dt"])
    dT_dV = (propeller(P, Va + 0.1, tr["dt"])[0] - T0) / 0.1
    dT_dt = (propeller(P, Va, min(tr["dt"] + 0.01, 1.0))[0] - propeller(P, Va, tr["dt"] - 0.01)[0]) / 0.02
    aV1 = rho * Va * S * cd / m - dT_dV / m
    aV2 = dT_dt / m
    wn_v = 0.6
    k["ki_V"] = wn_v ** 2 / aV2
    k["kp_V"] = max((2 * 0.9 * wn_v - aV1) / aV2, 0.01)


def design(P, speeds):
    """Trim and gains at each commanded airspeed (gain schedule on the command)."""
    out = {}
    for Va in speeds:
        tr = trim(P, Va)
        k = {"trim": tr}
        design_lateral(P, Va, k)
        design_longitudinal(P, Va, tr, k)
        out[Va] = k
    return out


class Autopilot:
    """Successive loop closure (ch. 6) at the command rate; integrators with anti-windup."""

    def __init__(self, gains, dt, h_c, theta0):
        self.gains, self.dt = gains, dt
        self.h_c = h_c
        self.i_h = theta0                   # the integrators hold their output (rad, rad, throttle)
        self.i_chi = 0.0
        self.i_V = 0.0
        self.r_lp = 0.0
        self.phi_c = 0.0
        self.h_f = None

    def step(self, Va_c, chi_c, m):
        """m: phi, theta, chi, p, q, r, Va, h (measurements). Returns da, de, dr, dt (book signs)."""
        k, dt = self.gains[Va_c], self.dt
        tr = k["trim"]
        # altitude: the barometer low-passed (sec. 8.3), then pitch from altitude
        self.h_f = m["h"] if self.h_f is None else self.h_f + (1 - math.exp(-3.0 * dt)) * (m["h"] - self.h_f)
        e_h = self.h_c - self.h_f
        theta_c = k["kp_h"] * e_h + self.i_h
        if abs(theta_c) < 15 * D2R:
            self.i_h += dt * k["ki_h"] * e_h
        theta_c = max(-15 * D2R, min(15 * D2R, theta_c))
        de = tr["de"] + k["kp_theta"] * (theta_c - m["theta"]) - k["kd_theta"] * m["q"]
        # course -> roll -> aileron
        e_chi = (chi_c - m["chi"] + math.pi) % (2 * math.pi) - math.pi
        if abs(e_chi) < 10 * D2R:
            self.i_chi += dt * k["ki_chi"] * e_chi
        phi_c = max(-30 * D2R, min(30 * D2R, k["kp_chi"] * e_chi + self.i_chi))
        step = 45 * D2R * dt                                   # bank command slewed at 45 deg/s
        phi_c = self.phi_c = max(self.phi_c - step, min(self.phi_c + step, phi_c))
        da = tr["da"] + k["kp_phi"] * (phi_c - m["phi"]) - k["kd_phi"] * m["p"]
        # yaw damper: r washed out
        self.r_lp += (1 - math.exp(-k["p_wo"] * dt)) * (m["r"] - self.r_lp)
        dr = tr["dr"] + k["kr"] * (m["r"] - self.r_lp)
        # airspeed -> throttle, the integrator frozen while the throttle saturates against it
        e_V = Va_c - m["Va"]
        dthr = tr["dt"] + k["kp_V"] * e_V + self.i_V
        if not ((dthr >= 1.0 and e_V > 0) or (dthr <= 0.0 and e_V < 0)):
            self.i_V += dt * k["ki_V"] * e_V
        return da, de, dr, max(0.0, min(1.0, dthr))


# ----------------------------------------------------------------------------------------------
# The identification schedule
# ----------------------------------------------------------------------------------------------
def sig3211(tau, dt):
    if tau < 0 or tau >= 7 * dt:
        return 0.0
    return (1.0, 1.0, 1.0, -1.0, -1.0, 1.0, -1.0)[int(tau / dt)]


def doublet(tau, dt):
    return 0.0 if tau < 0 or tau >= 2 * dt else (1.0 if tau < dt else -1.0)


def chirp(tau, T, f0, f1):
    """Logarithmic sweep f0 -> f1 over T s, 0.5-s cosine tapers at both ends."""
    if tau < 0 or tau >= T:
        return 0.0
    k = math.log(f1 / f0)
    ph = 2 * math.pi * f0 * T / k * (math.exp(tau / T * k) - 1.0)
    taper = min(1.0, tau / 0.5, (T - tau) / 0.5)
    return math.sin(ph) * (0.5 - 0.5 * math.cos(math.pi * taper))


# (start within a 100-s leg, axis 0 aileron / 1 elevator / 2 rudder, shape, amplitude deg)
LEG = [(15.0, 1, lambda s: sig3211(s, 0.3), 4.0),
       (22.0, 1, lambda s: doublet(s, 0.6), 4.0),
       (28.0, 0, lambda s: sig3211(s, 0.4), 5.0),
       (35.0, 0, lambda s: doublet(s, 0.8), 5.0),
       (42.0, 2, lambda s: doublet(s, 1.0), 7.0),
       (64.0, 2, lambda s: sig3211(s, 0.5), 7.0),
       (71.0, 1, lambda s: chirp(s, 10.0, 0.2, 3.0), 2.5),
       (84.0, 0, lambda s: chirp(s, 8.0, 0.3, 3.0), 4.0)]
COURSES = [(None, 90.0), (330.0, 240.0), (0.0, 120.0)]   # deg at the leg's start and at 50 s


class Schedule:
    def __init__(self, speeds, duration, chi0):
        self.speeds = speeds
        self.leg = duration / len(speeds)
        self.scale = self.leg / 100.0
        self.chi0 = chi0

    def commands(self, t):
        """Va_c (one of the design speeds), chi_c (rad) at time t."""
        i = min(int(t / self.leg), len(self.speeds) - 1)
        tau = (t - i * self.leg) / self.scale
        a, b = COURSES[i % len(COURSES)]
        chi = b if tau >= 50.0 else a
        return self.speeds[i], (self.chi0 if chi is None else chi * D2R)

    def excitation(self, t):
        """Increments (da, de, dr) in rad, book signs."""
        i = min(int(t / self.leg), len(self.speeds) - 1)
        tl = t - i * self.leg
        out = [0.0, 0.0, 0.0]
        for start, axis, shape, amp in LEG:
            out[axis] += amp * D2R * shape(tl - start * self.scale)
        return tuple(out)


# ----------------------------------------------------------------------------------------------
# Sensors (ch. 7)
# ----------------------------------------------------------------------------------------------
def isa_pressure(h_msl):
    return P0 * (1.0 - ISA_K * h_msl) ** ISA_N


def isa_altitude(p):
    return (1.0 - (p / P0) ** (1.0 / ISA_N)) / ISA_K


def ned_to_lla(pn, pe, pd):
    lat0, lon0, h0 = ORIGIN
    a, e2 = 6378137.0, 6.69437999014e-3
    s = math.sin(lat0 * D2R)
    RN = a / math.sqrt(1 - e2 * s * s)
    RM = RN * (1 - e2) / (1 - e2 * s * s)
    return (lat0 + pn / (RM + h0) / D2R, lon0 + pe / ((RN + h0) * math.cos(lat0 * D2R)) / D2R, h0 - pd)


class Sensors:
    """Book ch. 7 noise figures: gyro 0.13 deg/s, accel 0.0025 g, pitot 2 Pa, GNSS Gauss-Markov
    (k_GPS = 1/1100 s, 0.21/0.21/0.40 m per 1-s step, i.e. 0.21 m/sqrt(s) at any rate), velocity 0.05 m/s;
    baro 3 Pa (the book's 10 Pa is an older sensor's: tern's estimator, set for 4 Pa, rejected 72 % of
    it). Constant biases drawn per seed: gyro 0.003 rad/s, accel 0.05 m/s^2, baro 30 Pa (1 sigma)."""

    def __init__(self, rng, pitot_mode, rho):
        self.rng, self.pitot_mode, self.rho = rng, pitot_mode, rho
        self.gyro_bias = rng.normal(0.0, 0.003, 3)
        self.accel_bias = rng.normal(0.0, 0.05, 3)
        self.baro_bias = rng.normal(0.0, 30.0)
        self.gm = rng.normal(0.0, 1.0, 3) * np.array([0.5, 0.5, 1.0])

    def imu(self, f_body, pqr):
        n = self.rng.standard_normal(6)
        acc = [f_body[i] + self.accel_bias[i] + 0.0025 * G * n[i] for i in range(3)]
        gyr = [pqr[i] + self.gyro_bias[i] + 0.13 * D2R * n[3 + i] for i in range(3)]
        return acc + gyr

    def baro(self, alt_msl):
        return isa_pressure(alt_msl) + self.baro_bias + 3.0 * self.rng.standard_normal()

    def pitot(self, Va, ur):
        v = Va if self.pitot_mode == "full" else ur
        return 0.5 * self.rho * v * v + 2.0 * self.rng.standard_normal()

    def mag(self, R):
        m = mul_t(R, MAG_NED)
        return [m[i] + 1e-7 * self.rng.standard_normal() for i in range(3)]

    def gnss(self, pos, vel, Ts):
        decay = math.exp(-Ts / 1100.0)
        sig = np.array([0.21, 0.21, 0.40]) * math.sqrt(Ts)
        self.gm = decay * self.gm + sig * self.rng.standard_normal(3)
        lat, lon, alt = ned_to_lla(pos[0] + self.gm[0], pos[1] + self.gm[1], pos[2] + self.gm[2])
        v = [vel[0] + 0.05 * self.rng.standard_normal(), vel[1] + 0.05 * self.rng.standard_normal(),
             vel[2] + 0.08 * self.rng.standard_normal()]
        return lat, lon, alt, v


# ----------------------------------------------------------------------------------------------
# Tables
# ----------------------------------------------------------------------------------------------
class Table:
    def __init__(self, path, columns):
        self.path = path
        self.header = ",".join(["t [s]", "stamp [ns]"] + columns)
        self.rows = []

    def add(self, t, values, fmt="{:.9g}"):
        cells = [f"{t:.9f}", str(int(round(t * 1e9)))] + [
            v if isinstance(v, str) else (str(v) if isinstance(v, int) else fmt.format(v)) for v in values]
        self.rows.append(",".join(cells))

    def write(self):
        with open(self.path, "w") as f:
            f.write(self.header + "\n")
            f.write("\n".join(self.rows))
            f.write("\n")


def open_tables(out, excitation_table):
    top = os.path.join(out, "topics")
    os.makedirs(top, exist_ok=True)
    T = {
        "imu": Table(f"{top}/imu.csv", ["accel_x [m/s^2]", "accel_y [m/s^2]", "accel_z [m/s^2]",
                                        "gyro_x [rad/s]", "gyro_y [rad/s]", "gyro_z [rad/s]"]),
        "gnss": Table(f"{top}/gnss.csv", ["time_of_validity [ns]", "fix_type", "num_sats", "lat [deg]",
                                          "lon [deg]", "alt [m]", "vel_n [m/s]", "vel_e [m/s]",
                                          "vel_d [m/s]", "h_acc [m]", "v_acc [m]", "s_acc [m/s]",
                                          "hdop", "vdop"]),
        "baro": Table(f"{top}/baro.csv", ["pressure [Pa]"]),
        "diff_pressure": Table(f"{top}/diff_pressure.csv", ["pressure [Pa]"]),
        "mag": Table(f"{top}/mag.csv", ["field_x [T]", "field_y [T]", "field_z [T]"]),
        "actuators": Table(f"{top}/actuators.csv", ["delta_a [rad]", "delta_e [rad]", "delta_r [rad]",
                                                    "delta_t"]),
        "reference": Table(f"{top}/reference.csv", ["phi [rad]", "theta [rad]", "psi [rad]", "lat [deg]",
                                                    "lon [deg]", "alt [m]", "v_n [m/s]", "v_e [m/s]",
                                                    "v_d [m/s]", "w_n [m/s]", "w_e [m/s]"]),
        "truth": Table(f"{out}/book_truth.csv", [
            "alpha [rad]", "beta [rad]", "Va [m/s]", "phi [rad]", "theta [rad]", "psi [rad]",
            "p [rad/s]", "q [rad/s]", "r [rad/s]", "u [m/s]", "v [m/s]", "w [m/s]", "wind_n [m/s]",
            "wind_e [m/s]", "wind_d [m/s]", "delta_a [rad]", "delta_e [rad]", "delta_r [rad]",
            "delta_t", "pn [m]", "pe [m]", "h [m]"]),
    }
    if excitation_table:
        T["excitation"] = Table(f"{top}/excitation.csv", ["delta_a [rad]", "delta_e [rad]",
                                                          "delta_r [rad]", "delta_t"])
    return T


def write_yaml(args, P, t_last, notes):
    dt_imu = 1.0 / args.imu_rate
    lines = [
        "tern_sensor_log: 1",
        'source: "bench/book_sim.py: an independent simulator from Beard & McLain, Small Unmanned Aircraft"',
        f'origin: "book_sim.py --aircraft {args.aircraft} --seed {args.seed}"',
        "date: 2025-06-01                     # fixed: a synthetic flight (the magnetic model's date)",
        f'aircraft: "{P["name"]} ({args.aircraft})"',
        "estimator:",
        "  gnss_delay: 0.0",
        "  baro_delay: 0.0",
        "  diff_pressure_delay: 0.0",
        "  mag_delay: 0.0",
        f"  rho: {P['rho']}",
        "  gnss_antenna_position: [0, 0, 0]",
        "  imu_position: [0, 0, 0]",
        "  imu_mount: [0, 0, 0]",
        f"  imu_max_dt: {max(1.5 * dt_imu, 0.05):.6g}",
        f"  imu_timeout: {max(2.0 * dt_imu, 0.02):.6g}",
        f"  imu_reinit_gap: {max(5.0 * dt_imu, 0.5):.6g}",
        f"airborne: [0.0, {t_last:.9f}]",
        "notes:",
    ] + [f'  - "{n}"' for n in notes]
    with open(os.path.join(args.out, "sensor_log.yaml"), "w") as f:
        f.write("\n".join(lines) + "\n")


# ----------------------------------------------------------------------------------------------
# The flight
# ----------------------------------------------------------------------------------------------
def initial_state(P, tr, Va, h0, wind_ned):
    """Trimmed straight and level in the air mass, heading north, h0 above the origin."""
    x = list(trim_state(P, Va, tr["alpha"], tr["beta"]))
    x[2] = -h0
    R = rot_body_to_ned(0.0, x[7], 0.0)
    wb = mul_t(R, wind_ned)
    x[3] += wb[0]
    x[4] += wb[1]
    x[5] += wb[2]
    return tuple(x) + (tr["da"], tr["de"], tr["dr"])


def clip_cmd(P, c):
    ma, me, mr = P["max_delta_a"], P["max_delta_e"], P["max_delta_r"]
    return (max(-ma, min(ma, c[0])), max(-me, min(me, c[1])), max(-mr, min(mr, c[2])),
            max(0.0, min(1.0, c[3])))


class Flight:
    """The simulation loop: RK4 at k_sub x the IMU rate, sensors on IMU ticks, autopilot at cmd rate."""

    def __init__(self, args, P):
        self.args, self.P = args, P
        self.rng = np.random.default_rng(args.seed)
        self.k_sub = max(1, math.ceil(400.0 / args.imu_rate))
        self.h = 1.0 / (args.imu_rate * self.k_sub)
        self.wind = (args.wind[0], args.wind[1], 0.0)
        self.gains = design(P, args.speeds)
        Va0 = 25.0 if 25.0 in self.gains else args.speeds[0]
        self.tr0 = trim(P, Va0)
        self.x = initial_state(P, self.tr0, Va0, 100.0, self.wind)
        self.cmd = (self.tr0["da"], self.tr0["de"], self.tr0["dr"], self.tr0["dt"])
        self.dryden = Dryden(self.rng, self.h, on=args.turbulence == "light")
        for _ in range(int(120.0 / self.h)):                 # gusts started in their steady state
            self.dryden.step(Va0)
        self.sens = Sensors(self.rng, args.pitot, P["rho"])
        chi0 = math.atan2(*mul(rot_body_to_ned(*self.x[6:9]), self.x[3:6])[1::-1])
        self.sched = Schedule(args.speeds, args.duration, chi0)
        h_baro = isa_altitude(isa_pressure(ORIGIN[2] + 100.0) + self.sens.baro_bias) - ORIGIN[2]
        self.ap = Autopilot(self.gains, 1.0 / args.cmd_rate, h_baro, self.tr0["alpha"])
        self.T = open_tables(args.out, args.excitation_table)
        self.last = {"Va": Va0, "h": h_baro}
        self.stats = {k: [] for k in ("Va", "alpha", "h", "p", "q", "r", "phi", "beta")}

    def state_info(self):
        """Air data, body forces (no gravity), NED velocity and wind at the current state."""
        x, P = self.x, self.P
        R = rot_body_to_ned(x[6], x[7], x[8])
        gust = self.dryden.gust
        wb = wind_body(x, self.wind, gust)
        f, air = forces_moments(P, x, wb, x[12], x[13], x[14], self.cmd[3])
        vel = mul(R, x[3:6])
        gn = mul(R, gust)
        wind = (self.wind[0] + gn[0], self.wind[1] + gn[1], self.wind[2] + gn[2])
        return R, f, air, vel, wind

    def sample(self, i, t):
        """Every sensor due at IMU tick i (time t); returns what the autopilot reads."""
        a, x, P, T = self.args, self.x, self.P, self.T
        R, f, (Va, alpha, beta, ur), vel, wind = self.state_info()
        m = P["mass"]
        imu = self.sens.imu((f[0] / m, f[1] / m, f[2] / m), x[9:12])
        T["imu"].add(t, imu)
        gyro = imu[3:6]
        if due(i, a.imu_rate, 50.0):
            p = self.sens.baro(ORIGIN[2] - x[2])
            T["baro"].add(t, [p])
            self.last["h"] = isa_altitude(p) - ORIGIN[2]
            dp = self.sens.pitot(Va, ur)
            T["diff_pressure"].add(t, [dp])
            self.last["Va"] = math.sqrt(max(2.0 * dp / P["rho"], 0.0))
            T["mag"].add(t, self.sens.mag(R), fmt="{:.6e}")
            lat, lon, alt = ned_to_lla(x[0], x[1], x[2])
            T["reference"].add(t, [x[6], x[7], wrap(x[8]), f"{lat:.9f}", f"{lon:.9f}", alt, vel[0],
                                   vel[1], vel[2], wind[0], wind[1]])
        if i > 0 and due(i, a.imu_rate, 5.0):                  # first fix at 0.2 s: a 0 epoch is "unknown"
            lat, lon, alt, v = self.sens.gnss(x[0:3], vel, 0.2)
            T["gnss"].add(t, [int(round(t * 1e9)), 3, 12, f"{lat:.9f}", f"{lon:.9f}", alt, v[0], v[1],
                              v[2], 1.5, 2.5, 0.15, 0.8, 1.2])
        T["truth"].add(t, [alpha, beta, Va, x[6], x[7], wrap(x[8]), x[9], x[10], x[11], x[3], x[4],
                           x[5], wind[0], wind[1], wind[2], x[12], x[13], x[14], self.cmd[3],
                           x[0], x[1], -x[2]])
        for k, v in (("Va", Va), ("alpha", alpha), ("h", -x[2]), ("p", x[9]), ("q", x[10]),
                     ("r", x[11]), ("phi", x[6]), ("beta", beta)):
            self.stats[k].append(v)
        chi = math.atan2(vel[1], vel[0])
        return {"phi": x[6], "theta": x[7], "chi": chi, "p": gyro[0], "q": gyro[1], "r": gyro[2],
                "Va": self.last["Va"], "h": self.last["h"]}

    def run(self):
        a, P = self.args, self.P
        n_imu = int(round(a.duration * a.imu_rate))
        pending = []
        next_cmd = 0.0
        for i in range(n_imu + 1):
            t = i / a.imu_rate
            meas = self.sample(i, t)
            if t >= next_cmd - 1e-9:
                next_cmd += 1.0 / a.cmd_rate
                Va_c, chi_c = self.sched.commands(t)
                c = self.ap.step(Va_c, chi_c, meas)
                ex = self.sched.excitation(t)
                c = clip_cmd(P, (c[0] + ex[0], c[1] + ex[1], c[2] + ex[2], c[3]))
                self.T["actuators"].add(t, c)
                if "excitation" in self.T:
                    self.T["excitation"].add(t, list(ex) + [0.0])
                pending.append((i + a.cmd_delay_samples, c))
            while pending and pending[0][0] <= i:
                self.cmd = pending.pop(0)[1]
            if i == n_imu:
                break
            for _ in range(self.k_sub):
                gust = self.dryden.step(self.stats["Va"][-1])
                self.x = rk4(P, self.x, self.h, self.wind, gust, self.cmd)
            if -self.x[2] < 5.0 or not all(map(math.isfinite, self.x)):
                raise SystemExit(f"book_sim: crashed at t = {t:.2f} s: {self.x}")
        return n_imu / a.imu_rate


def due(i, base_rate, rate):
    """Whether IMU tick i is the first at or after a multiple of 1/rate."""
    k = base_rate / rate
    return math.floor(i / k + 1e-9) != math.floor((i - 1) / k + 1e-9) or i == 0


def wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


# ----------------------------------------------------------------------------------------------
# Main
# ----------------------------------------------------------------------------------------------
def summary(fl, wall):
    s = {k: np.array(v) for k, v in fl.stats.items()}
    d = 180.0 / math.pi
    print(f"book_sim: {fl.P['name']}, {len(s['Va'])} IMU samples, {wall:.1f} s wall clock")
    print(f"  Va       {s['Va'].min():6.2f} .. {s['Va'].max():6.2f} m/s")
    print(f"  alpha    {s['alpha'].min() * d:6.2f} .. {s['alpha'].max() * d:6.2f} deg")
    print(f"  beta     {s['beta'].min() * d:6.2f} .. {s['beta'].max() * d:6.2f} deg")
    print(f"  height   {s['h'].min():6.1f} .. {s['h'].max():6.1f} m above the origin")
    print(f"  bank     {s['phi'].min() * d:6.1f} .. {s['phi'].max() * d:6.1f} deg")
    print(f"  max |p| {np.abs(s['p']).max() * d:.1f}, |q| {np.abs(s['q']).max() * d:.1f}, "
          f"|r| {np.abs(s['r']).max() * d:.1f} deg/s")
    # the truth's sensor biases: here for the one who ran it, not in the log the estimator reads
    b = fl.sens
    print("  sensor biases (truth, not in the log): gyro " + " ".join(f"{v:.5f}" for v in b.gyro_bias) + " rad/s, accel "
          + " ".join(f"{v:.4f}" for v in b.accel_bias) + f" m/s^2, baro {b.baro_bias:.1f} Pa")
    warn = []
    if s["h"].min() < 30:
        warn.append("below 30 m")
    if s["Va"].min() < 15 or s["Va"].max() > 35:
        warn.append("airspeed outside 15..35 m/s")
    if fl.P["stall_blend"] and s["alpha"].max() > 0.8 * fl.P["alpha0"]:
        warn.append("alpha near the stall")
    print("  envelope: " + ("; ".join(warn) if warn else "ok"))


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--aircraft", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--duration", type=float, default=300.0)
    ap.add_argument("--imu-rate", type=float, default=200.0)
    ap.add_argument("--cmd-rate", type=float, default=50.0)
    ap.add_argument("--cmd-delay-samples", type=int, default=1)
    ap.add_argument("--turbulence", choices=("light", "none"), default="light")
    ap.add_argument("--wind", type=float, nargs=2, metavar=("N", "E"), default=(0.7, 3.9))
    ap.add_argument("--excitation-table", action="store_true")
    ap.add_argument("--pitot", choices=("body-x", "full"), default="full")
    ap.add_argument("--speeds", type=float, nargs="+", default=(20.0, 25.0, 30.0))
    args = ap.parse_args(argv)
    if not (args.duration > 0.0 and args.imu_rate > 0.0):
        ap.error(f"--duration {args.duration:g} s, --imu-rate {args.imu_rate:g} Hz: expected both > 0")
    if not 0.0 < args.cmd_rate <= args.imu_rate:
        ap.error(f"--cmd-rate {args.cmd_rate:g} Hz: expected > 0 and at most --imu-rate ({args.imu_rate:g} Hz)")
    if args.cmd_delay_samples < 0:
        ap.error(f"--cmd-delay-samples {args.cmd_delay_samples}: expected >= 0")
    if not all(v > 0.0 for v in args.speeds):
        ap.error(f"--speeds {' '.join(f'{v:g}' for v in args.speeds)}: expected airspeeds > 0 m/s")
    return args


def print_gains(fl):
    for Va, k in fl.gains.items():
        tr = k["trim"]
        print(f"  gains at {Va:g} m/s: " + ", ".join(f"{n} {k[n]:.4g}" for n in (
            "kp_phi", "kd_phi", "kp_chi", "ki_chi", "kr", "zeta_dr", "kp_theta", "kd_theta",
            "kp_h", "ki_h", "kp_V", "ki_V")) + f"; trim alpha {tr['alpha'] / D2R:.2f} deg, "
            f"delta_e {tr['de'] / D2R:.2f} deg, delta_t {tr['dt']:.3f}")


def log_notes(args, P, fl):
    """sensor_log.yaml's notes: what a reader of the log needs to know about this simulation."""
    delay_ms = args.cmd_delay_samples / args.imu_rate * 1e3
    pitot = "0.5 rho Va^2" if args.pitot == "full" else "0.5 rho u_r^2, the body-x flow"
    return [
        "simulated: Beard & McLain's equations (ch. 3, 4.2-4.4), sensors of ch. 7; no truth in topics/",
        "topics/reference.csv is the simulator's TRUE attitude, position, ground velocity and wind "
        "(steady + gust); book_truth.csv has the rest",
        f"actuators: stamped when the autopilot computed them (at an IMU sample, {args.cmd_rate:g} Hz); "
        f"the servo receives each {args.cmd_delay_samples} IMU sample(s) later ({delay_ms:g} ms)",
        f"servo first-order lag tau {P['tau']} s; book signs (delta_e > 0 nose down, delta_r > 0 nose left)",
        f"pitot: {args.pitot} ({pitot}), rho {P['rho']}",
        f"wind: steady N {args.wind[0]} E {args.wind[1]} m/s; Dryden turbulence {args.turbulence}",
        f"seed {args.seed}; speeds {' '.join(f'{v:g}' for v in args.speeds)} m/s",
    ]


def main(argv=None):
    args = parse_args(argv)
    P = load_aircraft(args.aircraft)
    os.makedirs(args.out, exist_ok=True)
    t0 = time.time()
    fl = Flight(args, P)
    print_gains(fl)
    t_last = fl.run()
    for tab in fl.T.values():
        tab.write()
    write_yaml(args, P, t_last, log_notes(args, P, fl))
    summary(fl, time.time() - t0)


if __name__ == "__main__":
    main(sys.argv[1:])
