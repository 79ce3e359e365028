#!/usr/bin/python3
"""altitude_oracle.py RUN_DIR [RUN_DIR ...]: how well could any estimator know the height above home?

For each flight log (`tern fly --log-level full`, a sim_aero flight), prints the RMSE of the height
above home (the change of height since the first valid estimate, the frame a mission's altitudes
are flown in) from 30 s on, at every GNSS fix:
  tern      the flight's estimate (state.csv);
  oracle    a two-state Kalman filter over the flight's own sensor errors that is told the world's
            noise models (read from the run's params.csv: the barometer's bias walk and static-port
            error, the GNSS vertical error's sigma and correlation time): the barometer's drift as a
            random walk, the GNSS vertical error as first-order Gauss-Markov, fed the difference of
            the two sensors' height errors. What an estimator that knew what the world hides could
            do with these sensors; no estimator on the vehicle may know it;
  baro      the barometer alone (ISA pressure altitude, static-port error included);
  gnss      the raw fixes.
The world's hidden parameters are the evaluation's, never the vehicle's (DEVELOPERS.md: the
simulator is the world, the estimator is the vehicle).
"""
import bisect
import csv
import math
import os
import sys

T0 = 30.0  # s: as bench_estimation


def isa_altitude(p):  # tern::isa_pressure_altitude (sdk/include/tern/math.hpp)
    return 44330.769 * (1.0 - (p / 101325.0) ** 0.190263)


def read(run, topic):
    with open(os.path.join(run, "topics", topic + ".csv")) as f:
        return list(csv.DictReader(f))


def world_params(run):
    with open(os.path.join(run, "params.csv")) as f:
        p = {r["parameter"]: r["value"] for r in csv.DictReader(f)}
    return {k: float(p["sim." + k]) for k in ("baro_bias_walk", "baro_static_error", "gnss_v_sigma", "gnss_tau")}


class Series:
    """Samples of one column by time, looked up at or after a time (as the host's latest value)."""

    def __init__(self, rows, column):
        self.t = [float(r["t [s]"]) for r in rows]
        self.v = [float(r[column]) for r in rows]

    def at(self, t):
        return self.v[min(bisect.bisect_left(self.t, t), len(self.v) - 1)]


class Oracle:
    """x = (baro drift b, GNSS vertical error e), both m; measurement b - e (the sensors' difference)."""

    def __init__(self, walk, sigma, tau):
        self.walk, self.sigma, self.tau = walk, sigma, tau
        self.b = self.e = 0.0
        self.P = [[0.0, 0.0], [0.0, sigma * sigma]]  # the baro was calibrated at home: b(0) = 0

    def update(self, dt, z, r=0.2**2):
        a = math.exp(-dt / self.tau)
        p00 = self.P[0][0] + self.walk**2 * dt
        p01 = a * self.P[0][1]
        p11 = a * a * self.P[1][1] + self.sigma**2 * (1.0 - a * a)
        self.e *= a
        s = p00 - 2.0 * p01 + p11 + r
        k0, k1 = (p00 - p01) / s, (p01 - p11) / s
        y = z - (self.b - self.e)
        self.b += k0 * y
        self.e += k1 * y
        n01 = p01 - k0 * (p01 - p11)
        self.P = [[p00 - k0 * (p00 - p01), n01], [n01, p11 - k1 * (p01 - p11)]]


def rms(v):
    return math.sqrt(sum(x * x for x in v) / len(v)) if v else float("nan")


def analyse(run):
    w = world_params(run)
    truth, state = read(run, "truth"), read(run, "state")
    h_true = Series(truth, "p_d [m]")
    est = Series(state, "p_d [m]")
    baro, pitot = Series(read(run, "baro"), "pressure [Pa]"), Series(read(run, "diff_pressure"), "pressure [Pa]")
    origin_alt = float(truth[0]["origin_alt [m]"])
    home = next(r for r in state if r["valid [bool]"] in ("1", "true"))
    t_home = float(home["t [s]"])
    home_true, home_est, home_baro = -h_true.at(t_home), -est.at(t_home), isa_altitude(baro.at(t_home))
    rho = 1.225 * (1.0 - 2.25577e-5 * origin_alt) ** 4.2559  # ISA density at the field
    oracle = Oracle(w["baro_bias_walk"] / (rho * 9.80665), w["gnss_v_sigma"], w["gnss_tau"])
    err = {"tern": [], "oracle": [], "baro": [], "gnss": []}
    t_prev = e_gnss_home = None
    for fix in read(run, "gnss"):
        t = float(fix["t [s]"])
        if t <= t_home:
            continue
        t_valid = float(fix["time_of_validity [ns]"]) * 1e-9
        up = -h_true.at(t) - home_true
        e_gnss = float(fix["alt [m]"]) - origin_alt + h_true.at(t_valid)  # the fix's error at its epoch
        if e_gnss_home is None:
            e_gnss_home = e_gnss
        h_baro = isa_altitude(baro.at(t)) - home_baro
        q = max(pitot.at(t), 0.0)
        e_baro = h_baro + w["baro_static_error"] * q / (rho * 9.80665) - up  # the drift, static error removed
        oracle.update(t - t_prev if t_prev is not None else 0.1, e_baro - e_gnss)
        t_prev = t
        if t < T0:
            continue
        err["tern"].append(-est.at(t) - home_est - up)
        err["oracle"].append(e_baro - oracle.b)
        err["baro"].append(h_baro - up)
        err["gnss"].append(e_gnss - e_gnss_home)
    return {k: rms(v) for k, v in err.items()}


def main(argv):
    if len(argv) < 2:
        print(__doc__.strip().splitlines()[0], file=sys.stderr)
        return 2
    print("height above home, RMSE m from %.0f s at the GNSS fixes" % T0)
    print("%-48s %7s %7s %7s %7s" % ("run", "tern", "oracle", "baro", "gnss"))
    for run in argv[1:]:
        try:
            r = analyse(run)
        except (OSError, KeyError, ValueError, StopIteration) as e:
            print("altitude_oracle: %s: %s (a sim_aero flight logged with --log-level full?)" % (run, e), file=sys.stderr)
            return 1
        print("%-48s %7.3f %7.3f %7.3f %7.3f" % (os.path.normpath(run)[-48:], r["tern"], r["oracle"], r["baro"], r["gnss"]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
