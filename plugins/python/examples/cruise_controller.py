"""A cruise controller in Python: successive loop closure after Beard & McLain, Small Unmanned
Aircraft, ch. 6 (course -> roll -> aileron, altitude -> pitch -> elevator, airspeed -> throttle),
as a tern Python plugin (docs/python.md, "A plugin in Python"). configs/missions/
python_controller.yaml swaps it in for the cruise, the C++ control_slc taking off, landing and
standing by as the fallback:

    - name: pyslc
      plugin: python_controller
      rate: 100
      params: {script: ../../plugins/python/examples/cruise_controller.py}
    phases: {takeoff: slc, climb: slc, cruise: pyslc, approach: slc, flare: slc, rollout: slc}
    fallback: slc

The defaults are configs/gains/anaconda.yaml's (the uavbook's design at Va = 17 m/s); its signs
are tern's: delta_e = -(-trim_e + u) with u the pitch loop's output, as control_common's
PitchLoop. When the phase router hands it the controls, take_over() sets each integrator so that
the first command equals the last one flown (bumpless transfer).
"""
import math


def saturate(x, low, high):
    return min(max(x, low), high)


def wrap_pi(angle):
    angle = math.fmod(angle + math.pi, 2.0 * math.pi)
    return (angle + 2.0 * math.pi if angle < 0.0 else angle) - math.pi


class Pid:
    """u = ff + kp e + ki integral(e) - kd ydot on [low, high]; trapezoidal integration, held
    while the output is saturated in the direction the error pushes (conditional integration)."""

    def __init__(self, kp, ki, kd, low, high):
        self.kp, self.ki, self.kd, self.low, self.high = kp, ki, kd, low, high
        self.integral, self.e_last = 0.0, None

    def output(self, e, ydot, ff, integral):
        return ff + self.kp * e + self.ki * integral - self.kd * ydot

    def update(self, e, ydot, dt, ff=0.0):
        candidate = self.integral + 0.5 * dt * (e + (e if self.e_last is None else self.e_last))
        u = self.output(e, ydot, ff, candidate)
        if self.low <= u <= self.high or (u > self.high and e < 0.0) or (u < self.low and e > 0.0):
            self.integral = candidate
        self.e_last = e
        return saturate(self.output(e, ydot, ff, self.integral), self.low, self.high)

    def initialise(self, u, e, ydot, ff=0.0):
        """The integral that makes the output u for this error: the command continues from u."""
        self.integral = (u - ff - self.kp * e + self.kd * ydot) / self.ki if self.ki != 0.0 else 0.0
        self.e_last = e


class CruiseController:
    inputs = {"state": "State", "controller_command": "ControllerCommand"}
    outputs = {"actuators": "Actuators"}
    params = {
        "course_kp": (2.77857, "rad/rad", 0.0, 20.0, "roll command per rad of course error"),
        "course_ki": (0.111143, "1/s", 0.0, 10.0, "course error integral gain"),
        "roll_kp": (1.86365, "rad/rad", 0.0, 20.0, "aileron per rad of roll error"),
        "roll_kd": (0.0, "s", 0.0, 5.0, "aileron per rad/s of roll rate"),
        "roll_max": (0.7854, "rad", 0.05, 1.2, "roll command limit"),
        "pitch_kp": (6.45791, "rad/rad", 0.0, 50.0, "elevator per rad of pitch error"),
        "pitch_ki": (15.0139, "1/s", 0.0, 100.0, "pitch error integral gain"),
        "pitch_kd": (0.368143, "s", 0.0, 5.0, "elevator per rad/s of pitch rate"),
        "altitude_kp": (0.156295, "rad/m", 0.0, 5.0, "pitch command per m of altitude error"),
        "altitude_ki": (0.0726738, "rad/(m s)", 0.0, 5.0, "altitude error integral gain"),
        "airspeed_kp": (0.161452, "1/(m/s)", 0.0, 5.0, "throttle per m/s of airspeed error"),
        "airspeed_ki": (0.146559, "1/(m s)", 0.0, 5.0, "airspeed error integral gain"),
        "trim_e": (0.167919, "rad", -0.6, 0.6, "elevator at trim"),
        "trim_t": (0.56762, "", 0.0, 1.0, "throttle at trim"),
        "max_a": (0.6981, "rad", 0.05, 1.0, "aileron limit"),
        "max_e": (0.61, "rad", 0.05, 1.0, "elevator limit"),
        "theta_max": (0.35, "rad", 0.0, 1.0, "pitch command's upper limit"),
        "theta_min": (-0.35, "rad", -1.0, 0.0, "pitch command's lower limit"),
    }

    def __init__(self):
        self.course = Pid(self.course_kp, self.course_ki, 0.0, -self.roll_max, self.roll_max)
        self.roll = Pid(self.roll_kp, 0.0, self.roll_kd, -self.max_a, self.max_a)
        self.altitude = Pid(self.altitude_kp, self.altitude_ki, 0.0, self.theta_min, self.theta_max)
        self.pitch = Pid(self.pitch_kp, self.pitch_ki, self.pitch_kd, -self.max_e, self.max_e)
        self.airspeed = Pid(self.airspeed_kp, self.airspeed_ki, 0.0, 0.0, 1.0)
        self.last_now = None
        self.handed = None  # the last command flown before take_over(), to start from

    def take_over(self, last_command):
        self.__init__()
        self.handed = last_command

    def step(self, now, inputs):
        x, c = inputs["state"], inputs["controller_command"]
        if x is None or c is None:
            return None
        dt = 0.0 if self.last_now is None else (now - self.last_now) * 1e-9
        self.last_now = now
        h, h_dot = -x.p_d, -x.v_d
        e_chi, e_h, e_Va = wrap_pi(c.chi_c - x.chi), c.h_c - h, c.Va_c - x.Va
        if self.handed is not None:  # bumpless: every loop starts from the command flown last
            a = self.handed
            phi_c = saturate(x.phi + (a.delta_a + self.roll_kd * x.p) / self.roll_kp, -self.roll_max, self.roll_max)
            theta_c = saturate(x.theta + (self.trim_e - a.delta_e + self.pitch_kd * x.q) / self.pitch_kp, self.theta_min, self.theta_max)
            self.course.initialise(phi_c, e_chi, 0.0, c.phi_ff)
            self.altitude.initialise(theta_c, e_h, h_dot)
            self.pitch.initialise(-a.delta_e, theta_c - x.theta, x.q, -self.trim_e)
            self.airspeed.initialise(a.delta_t, e_Va, 0.0, self.trim_t)
            self.handed = None
        phi_c = self.course.update(e_chi, 0.0, dt, c.phi_ff)
        theta_c = self.altitude.update(e_h, h_dot, dt)
        delta_a = self.roll.update(phi_c - x.phi, x.p, dt)
        delta_e = -self.pitch.update(theta_c - x.theta, x.q, dt, -self.trim_e)
        delta_t = self.airspeed.update(e_Va, 0.0, dt, self.trim_t)
        return {"actuators": {"delta_a": delta_a, "delta_e": delta_e, "delta_r": 0.0, "delta_t": delta_t}}
