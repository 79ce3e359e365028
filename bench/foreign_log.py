#!/usr/bin/python3
"""foreign_log.py RUN OUT [--command-delay MS] [--imu-rate HZ] [--actuator-rate HZ] [--start-height M] [--declare-airborne] [--no-pitot]:
a tern flight rewritten to look like another autopilot's log (issue 76: identification on the flights users bring).

What another autopilot's log differs by, each a switch, all on by default:
  * no excitation table: topics/excitation.csv is dropped (no PX4 or ArduPilot log has tern's signal
    generator's increments), and so are the simulator's truth and tern's own estimate;
  * commands that act after their stamps: every actuators row is stamped --command-delay ms (default 10)
    earlier than tern issued it (a servo bus, a mixer a cycle late);
  * other rates: the IMU block-averaged to --imu-rate Hz (default 200: an IMU's own output filter, stamped
    at the block's last sample), the commands sampled and held at --actuator-rate Hz (default 50);
  * a log that starts in the air: every table cut before the truth first stands --start-height m (default
    50) above its start, and every time moved so that the log starts at 0 (t and stamp; the GNSS's
    time_of_validity with them).
With --no-pitot the pitot's diff_pressure.csv is left out (an aircraft without one: the airspeed is then
the estimator's, from its wind).
sensor_log.yaml says what was done (notes), carries the IMU timing the estimator needs at that rate
(imu_max_dt, imu_timeout, imu_reinit_gap, as tern import writes them) and, with --declare-airborne, the
airborne window as an independent simulator would declare it: from the log's start to the touchdown (the truth's
last time 0.5 m above the ground; the landing's roll-out is not airborne). config.yaml (the
flight's estimator configuration) is kept: a user replays with their own vehicle's.
Returns/prints the time cut from the start (s), so that a bench can put the truth on the new clock.
"""
import argparse
import csv
import os
import shutil

SENSORS = ("imu", "gnss", "baro", "diff_pressure", "mag")


def read_table(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def write_table(path, header, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(header)
        w.writerows(rows)


def column(header, name):
    return [h.split(" [")[0] for h in header].index(name)


def retimed(header, rows, shift_s):
    """Rows with t, stamp (and a non-zero time_of_validity) moved by -shift_s."""
    it, ist = column(header, "t"), column(header, "stamp")
    names = [h.split(" [")[0] for h in header]
    itov = names.index("time_of_validity") if "time_of_validity" in names else None
    shift_ns = round(shift_s * 1e9)
    out = []
    for r in rows:
        r = list(r)
        r[it] = f"{float(r[it]) - shift_s:.9f}"
        r[ist] = str(int(r[ist]) - shift_ns)
        if itov is not None and r[itov] not in ("", "0"):
            r[itov] = str(int(r[itov]) - shift_ns)
        out.append(r)
    return out


def block_average(header, rows, hz):
    """IMU rows averaged over blocks of 1/hz s (numeric columns), each stamped at its last row."""
    it, ist = column(header, "t"), column(header, "stamp")
    out, block, current = [], [], None
    for r in rows:
        k = int(float(r[it]) * hz)
        if current is not None and k != current and block:
            out.append(average(block, it, ist))
            block = []
        current = k
        block.append(r)
    if block:
        out.append(average(block, it, ist))
    return out


def average(block, it, ist):
    last = list(block[-1])
    for j in range(len(last)):
        if j in (it, ist):
            continue
        try:
            last[j] = repr(sum(float(r[j]) for r in block) / len(block))
        except ValueError:
            pass
    return last


def sample_and_hold(header, rows, hz):
    """The command in force at each multiple of 1/hz s: the first row at or after it."""
    it = column(header, "t")
    out, next_t = [], None
    for r in rows:
        t = float(r[it])
        if next_t is None or t >= next_t:
            out.append(r)
            next_t = (int(t * hz) + 1) / hz
    return out


def start_time(run, height):
    """s: the truth's first time `height` m above its first sample (0 without truth)."""
    path = os.path.join(run, "topics", "truth.csv")
    if height <= 0 or not os.path.exists(path):
        return 0.0
    header, rows = read_table(path)
    it, ipd = column(header, "t"), column(header, "p_d")
    ground = float(rows[0][ipd])
    for r in rows:
        if ground - float(r[ipd]) > height:
            return float(r[it])
    raise SystemExit(f"foreign_log: {path}: the truth never stands {height} m above its start")


def touchdown_time(run):
    """s: the truth's last time more than 0.5 m above its first sample (the log's end without truth): where an
    independent simulator's declared airborne window ends (the landing's roll-out is on the ground)."""
    path = os.path.join(run, "topics", "truth.csv")
    if not os.path.exists(path):
        return None
    header, rows = read_table(path)
    it, ipd = column(header, "t"), column(header, "p_d")
    ground = float(rows[0][ipd])
    airborne = [float(r[it]) for r in rows if ground - float(r[ipd]) > 0.5]
    return airborne[-1] if airborne else None


def rewrite(run, out, command_delay_ms=10.0, imu_rate=200.0, actuator_rate=50.0, start_height=50.0, declare_airborne=False, pitot=True):
    cut = start_time(run, start_height)
    os.makedirs(os.path.join(out, "topics"), exist_ok=True)
    last_t = 0.0
    for name in SENSORS + ("actuators",):
        src = os.path.join(run, "topics", f"{name}.csv")
        if not os.path.exists(src) or (name == "diff_pressure" and not pitot):
            continue
        header, rows = read_table(src)
        it = column(header, "t")
        if name == "imu" and imu_rate > 0:
            rows = block_average(header, rows, imu_rate)
        if name == "actuators":
            if actuator_rate > 0:
                rows = sample_and_hold(header, rows, actuator_rate)
            rows = retimed(header, rows, command_delay_ms / 1000.0)
        rows = [r for r in retimed(header, rows, cut) if float(r[it]) >= 0.0]
        if name == "imu" and rows:
            last_t = float(rows[-1][it])
        write_table(os.path.join(out, "topics", f"{name}.csv"), header, rows)
    if os.path.exists(os.path.join(run, "config.yaml")):
        shutil.copyfile(os.path.join(run, "config.yaml"), os.path.join(out, "config.yaml"))
    dt = 1.0 / imu_rate if imu_rate > 0 else 0.0025
    lines = ["tern_sensor_log: 1", "estimator:", f"  imu_max_dt: {max(0.05, 1.5 * dt):g}", f"  imu_timeout: {max(0.02, 2 * dt):g}",
             f"  imu_reinit_gap: {max(0.5, 5 * dt):g}"]
    if declare_airborne:
        touchdown = touchdown_time(run)
        end = min(last_t, touchdown - cut) if touchdown is not None else last_t
        lines.append(f"airborne: [0, {end:.3f}]")
    lines += ["notes:", f'  - "rewritten from {os.path.abspath(run)} by bench/foreign_log.py: no excitation table, no truth"',
              f'  - "commands stamped {command_delay_ms:g} ms before they act; IMU {imu_rate:g} Hz (block means), '
              f'actuators {actuator_rate:g} Hz (held)"',
              f'  - "the log starts {cut:.3f} s into the flight ({start_height:g} m above its start), at t = 0"']
    if not pitot:
        lines.append('  - "no diff_pressure.csv: an aircraft without a pitot"')
    with open(os.path.join(out, "sensor_log.yaml"), "w") as f:
        f.write("\n".join(lines) + "\n")
    return cut


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run")
    ap.add_argument("out")
    ap.add_argument("--command-delay", type=float, default=10.0, help="ms (default 10)")
    ap.add_argument("--imu-rate", type=float, default=200.0, help="Hz (default 200; 0: as logged)")
    ap.add_argument("--actuator-rate", type=float, default=50.0, help="Hz (default 50; 0: as logged)")
    ap.add_argument("--start-height", type=float, default=50.0, help="m above the start where the log begins (0: the whole flight)")
    ap.add_argument("--declare-airborne", action="store_true", help="write sensor_log.yaml's airborne window")
    ap.add_argument("--no-pitot", action="store_true", help="leave the pitot's diff_pressure.csv out")
    a = ap.parse_args()
    cut = rewrite(a.run, a.out, a.command_delay, a.imu_rate, a.actuator_rate, a.start_height, a.declare_airborne, not a.no_pitot)
    print(f"foreign_log: {a.out} (cut {cut:.3f} s from the start)")


if __name__ == "__main__":
    main()
