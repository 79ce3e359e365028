"""tern plot: what it says on the command line: the text of --help (HELP), the usage line of a
wrong command line (USAGE) and an error's one line and exit status 1 (fail). Needs no numpy:
tern-plot names a missing numpy or matplotlib with it."""

import sys

PROG = "tern plot"
USAGE = ("usage: tern plot [--strict] [--out DIR] RUN_DIR [RUN_DIR ...] (run directories written by tern fly or tern "
         "replay; or one multi-vehicle run directory, with fleet.json)")

HELP = """tern-plot: PNG figures and an HTML page of tern flight logs; overlays of several runs.

Usage: tern plot [--strict] [--out DIR] RUN_DIR [RUN_DIR ...]   (or: tern-plot ...)

Reads the run directory `tern fly` or `tern replay` wrote (config.yaml, summary.json,
params.csv, topics/<topic>.csv; see core/host/record/flight_log.hpp) and writes into RUN_DIR/plots/:

  ground_track.png       north up, east on x, equal axes: true and estimated tracks, the
                         commanded path segments (current_path lines and orbit arcs, over the
                         stretch the aircraft flew them), the waypoints as flown (the last list
                         the planner published, topics/waypoints_items.csv; the list at the start
                         hollow; waypoints added in flight, by a mission edit over DDS or a
                         failsafe, starred with the time they appeared), failsafe, fallback and
                         handover positions (numbered X, named in the legend), mean true wind;
                         the legend below the map
  altitude.png           h = -p_d: true, estimated, commanded h_c
  airspeed.png           Va: true, estimated, commanded Va_c
  course.png             chi: true, estimated, commanded chi_c (deg, wrapped into -180..180, each
                         line broken where it wraps: no line across the axes; not drawn below a
                         ground speed Vg of 1 m/s, where the course is noise)
  roll_pitch.png         phi and theta: commanded (controller_internals), estimated, true (deg)
  actuators.png          delta_a, delta_e, delta_r (rad), delta_t: the commands, the limits of
                         the controller flying at each moment (params.csv: max_a, max_e, max_r,
                         min_t/max_t of control_slc/control_tecs, changes in flight included; which
                         controller flies: summary.json's handovers), the host's max_deflection,
                         the stretches at a limit shaded and their share of the time
  estimation_errors.png  estimate minus truth, one panel per quantity (n, e, h, phi, theta, psi,
                         Va), one colour per estimator instance, +-3 sigma bands from the logged
                         P_diag (attitude: the body-frame attitude-error variances through the
                         Euler-angle map, cross-covariances not logged); the raw GNSS fix minus
                         truth; RMSE in the legend over the window summary.json's metrics use
                         (from window_start_s, cruise only), named in the legend
  tune.png               a `tern tune` flight only (tune.csv): the tuned loop's command and
                         estimated response, each measured step's rise time and overshoot
  landing.png            a flight with a land item that reached the approach (tern_plot_landing.py),
                         in the runway's frame (along the runway heading from the path manager's
                         touchdown point, < 0 short; across, > 0 right; in the estimate's NED):
                         side view of the height above the touchdown point, the planned glide path
                         from the approach entry, the flare and decision heights, the true and
                         estimated trajectory of the last approach, flare and rollout (earlier
                         approaches that went around fainter), a closer view from the decision
                         height; top view of the tracks about the centre line; the aim point on
                         the field, summary.json's metrics.landing touchdown and the stop. No land
                         item: not drawn, no note; never approached: a note
  replay_attitude.png    a truth-free replay (topics/reference.csv, no truth; one run): roll,
                         pitch, yaw and course of tern's estimate, the reference estimator's and
                         the GNSS course; replay_track.png (north/east), replay_altitude.png,
                         replay_wind.png the same in the estimate's NED; replay_nis.png each
                         sensor's innovation test ratio over time (tern_plot_reference.py)
  index.html             the flight first: ground track, altitude and landing side by side on the
                         first screen (captions folded), then the other figures with their
                         captions, then the tables: summary.json's (flight, RMSE, phases,
                         handovers, failsafes, waypoint passages, instances), and
                         replay_report.json's (`tern replay`'s truth-free report) when there is one; relative
                         image paths: opens from disk, no server
  figures.json           per figure: file, caption, markers drawn, legend texts, RMSE values

Estimator instances: every topic with the State layout except truth (`state`, and e.g. `state_b`
of an instance remapped), named after the config's instance. A replay of a flight with that
flight's config (`tern replay RUN`) also draws the estimate recorded in flight.

Several RUN_DIRs: overlays for A/B comparison into RUN_A/plots/vs-<RUN_B>[+<RUN_C>...]/ (or
--out DIR), one colour per run, labelled by the run directory names (without tern fly's time
stamp when the rest differs): ground track, tracking (true and commanded), actuators and their
limits, estimation errors of each run's main estimator, and the index page. What differs between
the first run and each other one (tern_plot_compare.py: mission, sensor profile, duration, seed,
aircraft, plugin instances, phase table, parameters) is printed as one block before the plots
directory ("A/B: RUN_A vs RUN_B: these runs differ in: mission default vs my_ctl; ..."), with a
warning line when the missions differ, and shown at the top of the overlay's index.html.

A multi-vehicle run (FLEET_DIR with fleet.json, one run directory per vehicle in it; drawn alone):
each vehicle's figures into FLEET_DIR/plots/<vehicle>/, and into FLEET_DIR/plots/ (or --out DIR)
tracks.png (every vehicle from above in the world NED, one colour each, start and end, the
closest approach), altitude.png, separation.png (each pair's horizontal and 3-D distance,
summary.json's closest approach and min_distance) and index.html (tern_plot_fleet.py).

Estimate and truth are drawn in one frame: the estimator's NED is about its own origin (the first
GNSS fix), the simulator's about its own; the truth (and the GNSS fixes) are moved into the
estimator's frame, the frame of the path and the waypoints, with the two origins that both state
topics carry (as the flight summary compares them).

Every time figure carries shaded bands of the flight phases (one run; msg::Phase's preflight,
takeoff, climb, cruise, approach, flare, rollout, stopped, landing and loiter, each its colour)
and a marker (vertical line, labelled, styled by kind) at each phase change, controller handover,
fallback or state-loss-recovery engagement and failsafe event of summary.json (markers closer than a
label's width share one label, "a / b"). Each panel's legend stands in a strip above it, the phases'
legend below the time axis: no legend over the data. A missing topic is skipped
with a one-line note; a figure with nothing to draw is not written. Estimates are drawn only
where the state's `valid` flag is set.

Without a logged waypoint list, waypoints come from config.yaml's `mission:` section (inline
`waypoints:`, or `file:` relative to the original config, named in config.yaml's first line
"# resolved from <path>"; or the path_planner's `mission_file` parameter). tern waypoint files
and ROSplane mission files (repeated top-level `wp:` keys) are read; lat/lon/alt waypoints are
converted to NED about the estimator's origin (state.csv), like the planner does (WGS84, local
tangent plane).

Prints the files written and the plots directory; exit status 0. A missing or unusable
RUN_DIR is one error line and exit status 1. --strict: also exit 1 (after drawing) when
anything was noted as missing: a test that the log holds every field the figures use.

Needs Debian's python3-numpy, python3-matplotlib and python3-yaml. tern-plot reads the command
line; beside it (or in <prefix>/share/tern/plot): tern_plot_output.py (what goes into the plots
directory: every figure, index.html, a fleet's), tern_plot_load.py (a run directory read for the
figures), tern_plot_draw.py (colours, saving, decimation), tern_plot_track.py (ground_track.png),
tern_plot_control.py (tracking figures, actuators.png, tune.png), tern_plot_errors.py
(estimation_errors.png), tern_plot_log.py (what a run directory holds), tern_plot_mission.py (the
configured waypoints), tern_plot_yaml.py (PyYAML reading YAML as tern's C++ side does),
tern_plot_html.py (index.html), tern_plot_landing.py (landing.png), tern_plot_reference.py (a
truth-free replay's figures), tern_plot_fleet.py (a multi-vehicle run's), tern_plot_angles.py
(angles drawn wrapped), tern_plot_compare.py (what differs between A/B runs), tern_plot_layout.py
(where titles, legends, phase bands and marker labels go: nothing over the data),
tern_plot_usage.py (this text).
"""


def fail(msg):
    print(f"{PROG}: error: {msg}", file=sys.stderr)
    sys.exit(1)
