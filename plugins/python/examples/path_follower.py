"""The path follower in Python: Beard & McLain's vector fields (Small Unmanned Aircraft, ch. 10),
the same law as tern's C++ path_follower (plugins/path/src/follower.cpp), as a tern Python plugin
(docs/python.md, "A plugin in Python"). configs/missions/python_follower.yaml flies the default
mission with it:

    - name: follower
      plugin: python_path_follower
      rate: 100
      params: {script: ../../plugins/python/examples/path_follower.py}

Lines (eq. 10.8): chi_c = chi_q - chi_inf (2/pi) atan(k_path e_py), the altitude along the line
(eq. 10.5). Orbits (Alg. 4): chi_c = varphi + lambda (pi/2 + atan(k_orbit (d - rho) / rho)),
with the coordinated-turn roll feed-forward near the orbit (section 10.3).
"""
import math

from tern_sdk import GRAVITY  # m/s^2, the book's g: tern/math.hpp's kGravity, as the C++ follower's


def wrap_pi(angle):
    """angle wrapped to [-pi, pi), rad."""
    angle = math.fmod(angle + math.pi, 2.0 * math.pi)
    return (angle + 2.0 * math.pi if angle < 0.0 else angle) - math.pi


def unwrap_near(angle, reference):
    """angle moved by whole turns to within pi of reference, rad."""
    return reference + wrap_pi(angle - reference)


class PathFollower:
    inputs = {"state": "State", "current_path": "CurrentPath"}
    outputs = {"controller_command": "ControllerCommand"}
    # Defaults: ROSplane's Anaconda parameters (rosplane/params/anaconda_autopilot_params.yaml).
    params = {
        "chi_infty": (1.2, "rad", 0.01, math.pi / 2, "approach course to a line from far away (chi^inf)"),
        "k_path": (0.0175, "1/m", 1e-5, 10.0, "line vector-field gain: how sharply the field turns near the line"),
        "k_orbit": (0.5, "", 0.01, 100.0, "orbit vector-field gain: how sharply the field turns near the orbit"),
    }

    def __init__(self):
        self.commands = 0  # per-flight state: a new instance every flight
        self.warned_nan = False

    def step(self, now, inputs):
        s, path = inputs["state"], inputs["current_path"]
        if s is None or path is None:
            return None
        if not all(map(math.isfinite, (s.p_n, s.p_e, s.p_d, s.chi, path.Va_d, path.rho, path.r_n, path.r_e, path.r_d,
                                       path.q_n, path.q_e, path.q_d, path.c_n, path.c_e, path.c_d))):
            if not self.warned_nan:
                self.log.warning("state or current_path is not finite: no command this step")
            self.warned_nan = True
            return None
        self.commands += 1
        command = self.line(s, path) if path.path_type == 1 else self.orbit(s, path)
        command["chi_c"] = unwrap_near(command["chi_c"], s.chi)  # the course loop's error is chi_c - chi
        command["Va_c"] = path.Va_d
        return {"controller_command": command}

    def line(self, s, path):
        q_ne = math.hypot(path.q_n, path.q_e)
        if not q_ne > 1e-9:
            return {"chi_c": s.chi, "h_c": -path.r_d}
        chi_q = unwrap_near(math.atan2(path.q_e, path.q_n), s.chi)
        e_n, e_e = s.p_n - path.r_n, s.p_e - path.r_e
        e_py = -math.sin(chi_q) * e_n + math.cos(chi_q) * e_e  # cross-track error (eq. 10.2)
        along = e_n * (path.q_n / q_ne) + e_e * (path.q_e / q_ne)
        command = {"chi_c": chi_q - self.chi_infty * (2.0 / math.pi) * math.atan(self.k_path * e_py),
                   "h_c": -path.r_d - along * path.q_d / q_ne}
        if path.landing:  # a land item's glide path: never below the touchdown point
            command.update(landing=True, h_td=-path.r_d, h_c=max(command["h_c"], -path.r_d))
        return command

    def orbit(self, s, path):
        rho = path.rho if path.rho > 0.0 else 1.0
        dn, de = s.p_n - path.c_n, s.p_e - path.c_e
        d = math.hypot(dn, de)
        lam = 1.0 if getattr(path, "lambda") >= 0 else -1.0
        varphi = unwrap_near(math.atan2(de, dn) if d > 1e-9 else s.chi - getattr(path, "lambda") * math.pi / 2.0, s.chi)
        command = {"chi_c": varphi + lam * (math.pi / 2.0 + math.atan(self.k_orbit * (d - rho) / rho)), "h_c": -path.c_d}
        if abs(d - rho) < 0.5 * rho:
            V = s.Vg if math.isfinite(s.Vg) and s.Vg > 0.0 else (s.Va if math.isfinite(s.Va) else 0.0)
            crab = math.cos(s.chi - s.psi) if math.isfinite(s.psi) else 1.0
            command["phi_ff"] = lam * math.atan(V * V / (GRAVITY * rho * max(crab, 0.5)))
        return command

    def summary(self):
        return {"commands": float(self.commands)}
