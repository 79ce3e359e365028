/* core/apps/dds/interop/standin_controller.c: a stand-in for ROSplane's controller node, built on
 * Eclipse Cyclone DDS with types from standin_types.idl (written from the .msg files), not tern's
 * code. It has the controller's interfaces (rosplane/src/controller/controller_ros.cpp):
 *   subscribes rt/estimated_state (rosplane_msgs/msg/State) and rt/controller_command
 *   (rosplane_msgs/msg/ControllerCommands), publishes rt/command (rosflight_msgs/msg/Command,
 *   MODE_PASS_THROUGH, u[0] throttle, u[3] aileron, u[4] elevator, u[5] rudder, rad), all with
 *   rclcpp's default QoS (reliable, volatile, keep last 10);
 * and flies a successive-loop-closure autopilot (Beard & McLain, Small Unmanned Aircraft, ch. 6):
 *   course -> roll (PI, roll feed-forward phi_ff, roll-rate slew limit) -> aileron (PD, with the
 *   commanded roll rate fed forward), yaw damper (washed-out yaw rate) -> rudder,
 *   altitude -> pitch (PI) -> elevator (PID on pitch, pitch rate damping; uavbook sign: positive
 *   delta_e is nose down), airspeed -> throttle (PI).
 * Gains from a flat `name: value` file (configs/gains/anaconda.yaml, control_slc's names).
 * Lockstep: it answers the state and command stamped T (the host's tick) with a command stamped T,
 * once both have arrived; dt is the difference of successive stamps.
 * Usage: standin_controller DOMAIN GAINS_FILE [IDLE_S]: exits 0 after IDLE_S (default 10) seconds
 * without input once it has answered at least once (printing what it did), 1 on an error. */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <dds/dds.h>

#include "standin_types.h"

typedef struct {
  double kp, ki, kd, u_min, u_max;
  double integrator, e_prev;
  int primed;
} loop_t;

typedef struct {
  double course_kp, course_ki, roll_kp, roll_kd, roll_ki, roll_ff, roll_rate_max, roll_max, max_a;
  double yaw_damper_kr, yaw_damper_p_wo, max_r;
  double altitude_kp, altitude_ki, theta_max, theta_min;
  double pitch_kp, pitch_ki, pitch_kd, trim_e, max_e;
  double airspeed_kp, airspeed_ki, trim_t, max_t, min_t;
} gains_t;

static volatile sig_atomic_t stop_requested = 0;
static void on_signal(int s) {
  (void)s;
  stop_requested = 1;
}

static double sat(double x, double lo, double hi) { return x < lo ? lo : (x > hi ? hi : x); }
static double wrap_pi(double a) {
  while (a > M_PI) a -= 2.0 * M_PI;
  while (a < -M_PI) a += 2.0 * M_PI;
  return a;
}

/* u = kp e + ki I - kd ydot + ff, saturated; trapezoidal integration that stops growing into a
 * saturated output (anti-windup), integrator bounded to half the output span over ki. */
static double pid_update(loop_t* c, double e, double ydot, double dt, double ff) {
  double I = c->integrator;
  if (dt > 0.0 && c->ki != 0.0) {
    const double lim = 0.5 * (c->u_max - c->u_min) / fabs(c->ki);
    const double cand = sat(I + 0.5 * dt * (e + (c->primed ? c->e_prev : e)), -lim, lim);
    const double u_try = c->kp * e + c->ki * cand - c->kd * ydot + ff;
    if (!((u_try > c->u_max && cand > I) || (u_try < c->u_min && cand < I))) I = cand;
  }
  c->integrator = I;
  c->e_prev = e;
  c->primed = 1;
  return sat(c->kp * e + c->ki * I - c->kd * ydot + ff, c->u_min, c->u_max);
}

static int read_gains(const char* file, gains_t* g) {
  struct {
    const char* name;
    double* v;
  } keys[] = {{"course_kp", &g->course_kp},
              {"course_ki", &g->course_ki},
              {"roll_kp", &g->roll_kp},
              {"roll_kd", &g->roll_kd},
              {"roll_ki", &g->roll_ki},
              {"roll_ff", &g->roll_ff},
              {"roll_rate_max", &g->roll_rate_max},
              {"roll_max", &g->roll_max},
              {"max_a", &g->max_a},
              {"yaw_damper_kr", &g->yaw_damper_kr},
              {"yaw_damper_p_wo", &g->yaw_damper_p_wo},
              {"max_r", &g->max_r},
              {"altitude_kp", &g->altitude_kp},
              {"altitude_ki", &g->altitude_ki},
              {"theta_max", &g->theta_max},
              {"theta_min", &g->theta_min},
              {"pitch_kp", &g->pitch_kp},
              {"pitch_ki", &g->pitch_ki},
              {"pitch_kd", &g->pitch_kd},
              {"trim_e", &g->trim_e},
              {"max_e", &g->max_e},
              {"airspeed_kp", &g->airspeed_kp},
              {"airspeed_ki", &g->airspeed_ki},
              {"trim_t", &g->trim_t},
              {"max_t", &g->max_t},
              {"min_t", &g->min_t}};
  const size_t n = sizeof keys / sizeof keys[0];
  int found[64] = {0};
  FILE* f = fopen(file, "r");
  if (!f) {
    fprintf(stderr, "standin_controller: cannot open %s\n", file);
    return -1;
  }
  char line[512], name[128];
  double v;
  while (fgets(line, sizeof line, f))
    if (line[0] != '#' && sscanf(line, " %127[A-Za-z0-9_]: %lf", name, &v) == 2)
      for (size_t i = 0; i < n; ++i)
        if (strcmp(name, keys[i].name) == 0) {
          *keys[i].v = v;
          found[i] = 1;
        }
  fclose(f);
  for (size_t i = 0; i < n; ++i)
    if (!found[i]) {
      fprintf(stderr, "standin_controller: %s: no gain '%s'\n", file, keys[i].name);
      return -1;
    }
  return 0;
}

typedef struct {
  gains_t g;
  loop_t course, roll, altitude, pitch, airspeed;
  double phi_c_prev, p_c, wo_y, wo_x_prev;
  int shaped;
} autopilot_t;

static void autopilot_init(autopilot_t* a) {
  const gains_t* g = &a->g;
  a->course = (loop_t){g->course_kp, g->course_ki, 0.0, -g->roll_max, g->roll_max, 0, 0, 0};
  a->roll = (loop_t){g->roll_kp, g->roll_ki, g->roll_kd, -g->max_a, g->max_a, 0, 0, 0};
  a->altitude = (loop_t){g->altitude_kp, g->altitude_ki, 0.0, g->theta_min, g->theta_max, 0, 0, 0};
  a->pitch = (loop_t){g->pitch_kp, g->pitch_ki, g->pitch_kd, -g->max_e, g->max_e, 0, 0, 0};
  a->airspeed = (loop_t){g->airspeed_kp, g->airspeed_ki, 0.0, g->min_t, g->max_t, 0, 0, 0};
  a->shaped = 0;
}

/* One step: surfaces (rad) and throttle into u[] as ROSplane's controller packs them. */
static void autopilot_step(autopilot_t* a, const rosplane_msgs_msg_dds__State_* x, const rosplane_msgs_msg_dds__ControllerCommands_* c,
                           double dt, float u[10]) {
  const gains_t* g = &a->g;
  /* lateral: course -> roll command (slew-limited, its rate fed forward) -> aileron; yaw damper */
  double phi_c = pid_update(&a->course, wrap_pi(c->chi_c - x->chi), x->r, dt, c->phi_ff);
  if (a->shaped && g->roll_rate_max > 0.0 && dt > 0.0)
    phi_c = sat(phi_c, a->phi_c_prev - g->roll_rate_max * dt, a->phi_c_prev + g->roll_rate_max * dt);
  a->p_c = (a->shaped && dt > 0.0) ? (phi_c - a->phi_c_prev) / dt : 0.0;
  a->phi_c_prev = phi_c;
  const double delta_a = pid_update(&a->roll, phi_c - x->phi, x->p, dt, g->roll_ff * a->p_c);
  if (a->shaped && dt > 0.0) {
    const double k = g->yaw_damper_p_wo * dt;
    a->wo_y = (2.0 - k) / (2.0 + k) * a->wo_y + 2.0 / (2.0 + k) * (x->r - a->wo_x_prev);
  } else {
    a->wo_y = 0.0;
  }
  a->wo_x_prev = x->r;
  const double delta_r = sat(g->yaw_damper_kr * a->wo_y, -g->max_r, g->max_r);
  /* longitudinal: altitude -> pitch command -> elevator (nose down positive); airspeed -> throttle */
  const double theta_c = pid_update(&a->altitude, c->h_c - (-x->p_d), 0.0, dt, 0.0);
  const double delta_e = -pid_update(&a->pitch, theta_c - x->theta, x->q, dt, -g->trim_e);
  const double delta_t = pid_update(&a->airspeed, c->va_c - x->va, 0.0, dt, g->trim_t);
  a->shaped = 1;
  memset(u, 0, 10 * sizeof u[0]);
  u[0] = (float)delta_t;
  u[3] = (float)delta_a;
  u[4] = (float)delta_e;
  u[5] = (float)delta_r;
}

static dds_qos_t* rclcpp_default_qos(void) { /* reliable, volatile, keep last 10 */
  dds_qos_t* q = dds_create_qos();
  dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
  dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 10);
  return q;
}

static int64_t stamp_ns(const builtin_interfaces_msg_dds__Time_* t) { return (int64_t)t->sec * 1000000000 + t->nanosec; }

int main(int argc, char** argv) {
  if (argc < 3) {
    fprintf(stderr, "usage: standin_controller DOMAIN GAINS_FILE [IDLE_S]\n");
    return 1;
  }
  autopilot_t ap;
  memset(&ap, 0, sizeof ap);
  if (read_gains(argv[2], &ap.g) != 0) return 1;
  autopilot_init(&ap);
  const double idle_s = argc > 3 ? atof(argv[3]) : 10.0;
  signal(SIGTERM, on_signal);
  signal(SIGINT, on_signal);

  const dds_entity_t pp = dds_create_participant((dds_domainid_t)atoi(argv[1]), NULL, NULL);
  if (pp < 0) {
    fprintf(stderr, "standin_controller: no participant: %s\n", dds_strretcode(-pp));
    return 1;
  }
  dds_qos_t* q = rclcpp_default_qos();
  const dds_entity_t ts = dds_create_topic(pp, &rosplane_msgs_msg_dds__State__desc, "rt/estimated_state", NULL, NULL);
  const dds_entity_t tc = dds_create_topic(pp, &rosplane_msgs_msg_dds__ControllerCommands__desc, "rt/controller_command", NULL, NULL);
  const dds_entity_t to = dds_create_topic(pp, &rosflight_msgs_msg_dds__Command__desc, "rt/command", NULL, NULL);
  const dds_entity_t rs = dds_create_reader(pp, ts, q, NULL), rc = dds_create_reader(pp, tc, q, NULL);
  const dds_entity_t w = dds_create_writer(pp, to, q, NULL);
  dds_delete_qos(q);
  if (rs < 0 || rc < 0 || w < 0) {
    fprintf(stderr, "standin_controller: cannot create readers/writer\n");
    return 1;
  }
  const dds_entity_t ws = dds_create_waitset(pp);
  dds_set_status_mask(rs, DDS_DATA_AVAILABLE_STATUS);
  dds_set_status_mask(rc, DDS_DATA_AVAILABLE_STATUS);
  dds_waitset_attach(ws, rs, rs);
  dds_waitset_attach(ws, rc, rc);
  printf("standin_controller: domain %s, gains %s: waiting on rt/estimated_state and rt/controller_command\n", argv[1], argv[2]);
  fflush(stdout);

  rosplane_msgs_msg_dds__State_ state, s_in;
  rosplane_msgs_msg_dds__ControllerCommands_ cmd, c_in;
  memset(&state, 0, sizeof state);
  memset(&cmd, 0, sizeof cmd);
  int64_t state_t = -1, cmd_t = -1, done_t = -1;
  long answered = 0;
  dds_time_t last_input = dds_time();
  while (!stop_requested) {
    dds_waitset_wait(ws, NULL, 0, DDS_MSECS(200));
    void* p[1];
    dds_sample_info_t info;
    p[0] = &s_in;
    memset(&s_in, 0, sizeof s_in);
    while (dds_take(rs, p, &info, 1, 1) == 1) {
      if (info.valid_data) {
        state = s_in;
        state.header.frame_id = NULL; /* s_in's string, freed below */
        state_t = stamp_ns(&s_in.header.stamp);
        last_input = dds_time();
      }
      dds_sample_free(&s_in, &rosplane_msgs_msg_dds__State__desc, DDS_FREE_CONTENTS); /* the strings a take allocates */
      memset(&s_in, 0, sizeof s_in);
    }
    p[0] = &c_in;
    memset(&c_in, 0, sizeof c_in);
    while (dds_take(rc, p, &info, 1, 1) == 1) {
      if (info.valid_data) {
        cmd = c_in;
        cmd.header.frame_id = NULL;
        cmd_t = stamp_ns(&c_in.header.stamp);
        last_input = dds_time();
      }
      dds_sample_free(&c_in, &rosplane_msgs_msg_dds__ControllerCommands__desc, DDS_FREE_CONTENTS);
      memset(&c_in, 0, sizeof c_in);
    }
    if (state_t >= 0 && state_t == cmd_t && state_t > done_t) {
      const double dt = done_t < 0 ? 0.0 : (double)(state_t - done_t) * 1e-9;
      rosflight_msgs_msg_dds__Command_ out;
      memset(&out, 0, sizeof out);
      out.header.stamp = state.header.stamp;
      out.header.frame_id = "";
      out.mode = rosflight_msgs_msg_Command_Constants_MODE_PASS_THROUGH;
      out.ignore = 0;
      autopilot_step(&ap, &state, &cmd, dt, out.u);
      if (dds_write(w, &out) != DDS_RETCODE_OK) {
        fprintf(stderr, "standin_controller: write failed\n");
        return 1;
      }
      done_t = state_t;
      ++answered;
    }
    if (answered > 0 && dds_time() - last_input > DDS_SECS(idle_s)) break;
  }
  printf("standin_controller: answered %ld ticks, last stamp %.3f s\n", answered, (double)done_t * 1e-9);
  dds_delete(pp);
  return answered > 0 ? 0 : 1;
}
