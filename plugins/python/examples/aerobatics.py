"""Aerobatics in Python: rolls and loops flown through the surfaces between stretches of cruise, for
testing an estimator where attitude and heading change fastest (issue 61: the magnetometer and
the GNSS-course yaw through rolls and loops). configs/missions/aerobatics.yaml flies the default
mission's hourglass with it in cruise; control_slc takes off and lands.

Between manoeuvres it is the cruise controller (cruise_controller.py, successive loop closure).
Every `interval` seconds of cruise it flies the next manoeuvre of the sequence, open loop on the
surfaces, until the body rate integrated since its start has turned the aircraft through a full
turn (less `lead`, the rotation the recovery still carries):
  roll_right, roll_left   the aileron at `roll_aileron` (0.5 rad), elevator and throttle as at the start
  loop                    elevator pulled by `loop_pull` from the trim, full throttle, the wings held
                          in the loop's plane (the aileron keeps the body's y axis horizontal,
                          upright or inverted, from the estimate's attitude, and damps the roll rate)
then hands back to the cruise loops, started from the surfaces flown last (bumpless). The
manoeuvres read only the estimate's body rates (p, q: the gyros'), never the simulator's truth.
"""
import math
import types

from cruise_controller import CruiseController

SEQUENCE = ("roll_right", "roll_left", "loop")


class Aerobatics(CruiseController):
    params = dict(CruiseController.params, **{
        "interval": (15.0, "s", 3.0, 600.0, "cruise between two manoeuvres"),
        "roll_aileron": (0.5, "rad", 0.05, 0.7, "aileron of a roll"),
        "loop_pull": (0.35, "rad", 0.05, 0.7, "elevator pulled from the trim in a loop"),
        "lead": (0.35, "rad", 0.0, 1.5, "rotation left when the manoeuvre hands back to the cruise loops"),
        "loop_wings_kp": (1.0, "rad", 0.0, 5.0, "loop: aileron per rad of roll out of the loop's plane"),
        "loop_wings_kd": (0.1, "s", 0.0, 1.0, "loop: aileron per rad/s of roll rate"),
    })

    def __init__(self):
        super().__init__()
        self.next_at = None  # ns: when the next manoeuvre starts
        self.manoeuvre = None
        self.turned = 0.0  # rad, body rate integrated since the manoeuvre's start
        self.flown = 0
        self.last = {"delta_a": 0.0, "delta_e": self.trim_e, "delta_r": 0.0, "delta_t": self.trim_t}

    def step(self, now, inputs):
        x = inputs["state"]
        if x is None or inputs["controller_command"] is None:
            return None
        if self.next_at is None:
            self.next_at = now + int(self.interval * 1e9)
        if self.manoeuvre is None and now >= self.next_at:
            self.manoeuvre, self.turned = SEQUENCE[self.flown % len(SEQUENCE)], 0.0
            self.log.info("t=%.2f s: %s", now * 1e-9, self.manoeuvre)
        if self.manoeuvre is None:
            out = super().step(now, inputs)
            if out is not None:
                self.last = out["actuators"]
            return out
        dt = 0.0 if self.last_now is None else (now - self.last_now) * 1e-9
        self.last_now = now
        rate = x.q if self.manoeuvre == "loop" else x.p
        self.turned += rate * dt
        if abs(self.turned) >= 2.0 * math.pi - self.lead:
            self.manoeuvre, self.flown = None, self.flown + 1
            self.next_at = now + int(self.interval * 1e9)
            self.handed = types.SimpleNamespace(**self.last)  # the cruise loops start from the surfaces flown last
            return super().step(now, inputs)
        if self.manoeuvre == "loop":
            y_down = 2.0 * (x.quat_y * x.quat_z + x.quat_w * x.quat_x)  # down components of the body y and z axes
            z_down = 1.0 - 2.0 * (x.quat_x * x.quat_x + x.quat_y * x.quat_y)
            bank = math.atan2(y_down, z_down)  # the roll out of the loop's plane, upright or inverted alike
            bank -= math.copysign(math.pi, bank) if abs(bank) > math.pi / 2 else 0.0
            delta_a = -self.loop_wings_kp * bank - self.loop_wings_kd * x.p
            command = dict(self.last, delta_a=max(-self.max_a, min(self.max_a, delta_a)), delta_e=self.trim_e - self.loop_pull, delta_t=1.0)
        else:
            sign = 1.0 if self.manoeuvre == "roll_right" else -1.0
            command = dict(self.last, delta_a=sign * self.roll_aileron)
        self.last = command
        return {"actuators": command}

    def take_over(self, last_command):  # the counters of the flight outlive a handover
        flown, next_at = self.flown, self.next_at
        super().take_over(last_command)
        self.flown, self.next_at = flown, next_at

    def summary(self):
        return {"manoeuvres": float(self.flown)}
