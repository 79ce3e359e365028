/* core/apps/dds/interop/cyclone_gcs.c: a stand-in for ROSplane's ground station and estimator, built on
 * Eclipse Cyclone DDS with types from ros2_types.idl (written from the .msg files, not tern's IDL).
 * Against a running `tern fly --dds` (sim time) on DDS domain argv[1], namespace "tern", loopback:
 * subscribes with the QoS ROSplane's nodes use (rclcpp: a depth alone is reliable, volatile) to
 *   - what rosplane_gcs subscribes to (rosplane_gcs/src/rviz_waypoint_publisher.cpp,
 *     RvizWaypointPublisher::RvizWaypointPublisher): estimated_state (reliable, volatile, 10),
 *     waypoint_path (reliable, transient-local, 20);
 *   - what ROSplane's estimator subscribes to (rosplane/src/ekf/estimator_ros.cpp,
 *     EstimatorROS::EstimatorROS, all reliable, volatile, 10): imu/data, gnss, baro, airspeed,
 *     magnetometer, status;
 *   - /clock as rclcpp's TimeSource does (ClockQoS: best-effort, volatile, 1).
 * Each topic must match (no incompatible QoS), its samples must decode to values in range, their
 * stamps must advance and lie in sim time (within /clock's range), and /clock must advance by at
 * least 2 s. Prints a transcript; exit 0 when every check holds, 1 with the failing ones. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <dds/dds.h>

#include "ros2_types.h"

#define MATCH_TIMEOUT DDS_SECS(30)
#define RUN_TIMEOUT DDS_SECS(60)

typedef const char* (*check_fn)(const void* sample); /* NULL when the sample is sensible, else why not */
typedef const builtin_interfaces_msg_dds__Time_* (*stamp_fn)(const void* sample);

typedef struct {
  const char* name; /* DDS topic name */
  const dds_topic_descriptor_t* desc;
  dds_reliability_kind_t reliability;
  dds_durability_kind_t durability;
  int32_t depth;
  const char* source; /* the ROSplane file whose subscription this is */
  check_fn check;
  stamp_fn stamp;
  int min_samples;
  /* results */
  dds_entity_t reader;
  void* sample;
  int samples;
  int stamps_back; /* stamps that went backwards */
  double first_stamp, last_stamp, min_stamp, max_stamp;
  const char* bad; /* first failed check */
} topic_t;

static double seconds(const builtin_interfaces_msg_dds__Time_* t) { return t->sec + t->nanosec * 1e-9; }
static int finite3(double a, double b, double c) { return isfinite(a) && isfinite(b) && isfinite(c); }

static const builtin_interfaces_msg_dds__Time_* state_stamp(const void* s) {
  return &((const rosplane_msgs_msg_dds__State_*)s)->header.stamp;
}
static const char* check_state(const void* p) {
  const rosplane_msgs_msg_dds__State_* s = p;
  const double qn = sqrt(s->quat.w * s->quat.w + s->quat.x * s->quat.x + s->quat.y * s->quat.y + s->quat.z * s->quat.z);
  if (!finite3(s->p_n, s->p_e, s->p_d) || fabs(s->p_d) > 5000) return "position not finite or |p_d| > 5 km";
  if (!(s->va >= 0 && s->va < 60)) return "va outside [0, 60) m/s";
  if (fabs(qn - 1.0) > 0.01) return "quat not a unit quaternion";
  if (!(fabs(s->phi) <= M_PI && fabs(s->theta) <= M_PI / 2 + 1e-3)) return "phi/theta out of range";
  return NULL;
}
static const builtin_interfaces_msg_dds__Time_* waypoint_stamp(const void* s) {
  return &((const rosplane_msgs_msg_dds__Waypoint_*)s)->header.stamp;
}
static const char* check_waypoint(const void* p) {
  const rosplane_msgs_msg_dds__Waypoint_* w = p;
  if (w->clear_wp_list) return NULL;
  if (!finite3(w->w[0], w->w[1], w->w[2])) return "w not finite";
  if (!(w->va_d > 0 && w->va_d < 60)) return "va_d outside (0, 60) m/s";
  return NULL;
}
static const builtin_interfaces_msg_dds__Time_* imu_stamp(const void* s) { return &((const sensor_msgs_msg_dds__Imu_*)s)->header.stamp; }
static const char* check_imu(const void* p) {
  const sensor_msgs_msg_dds__Imu_* m = p;
  const geometry_msgs_msg_dds__Vector3_* a = &m->linear_acceleration;
  const geometry_msgs_msg_dds__Vector3_* g = &m->angular_velocity;
  const double an = sqrt(a->x * a->x + a->y * a->y + a->z * a->z);
  /* specific force: g at rest, near 0 in a pushover, under 10 g in any flight of a small aircraft */
  if (!(an < 100)) return "|linear_acceleration| not below 100 m/s^2";
  if (!(fabs(g->x) < 20 && fabs(g->y) < 20 && fabs(g->z) < 20)) return "angular_velocity beyond 20 rad/s";
  return NULL;
}
static const builtin_interfaces_msg_dds__Time_* gnss_stamp(const void* s) {
  return &((const rosflight_msgs_msg_dds__GNSS_*)s)->header.stamp;
}
static const char* check_gnss(const void* p) {
  const rosflight_msgs_msg_dds__GNSS_* m = p;
  if (m->fix_type > 5) return "fix_type > 5";
  if (!(fabs(m->lat) <= 90 && fabs(m->lon) <= 180)) return "lat/lon out of range";
  if (!finite3(m->vel_n, m->vel_e, m->vel_d) || fabs(m->vel_n) > 100 || fabs(m->vel_e) > 100) return "velocity beyond 100 m/s";
  return NULL;
}
static const builtin_interfaces_msg_dds__Time_* baro_stamp(const void* s) {
  return &((const rosflight_msgs_msg_dds__Barometer_*)s)->header.stamp;
}
static const char* check_baro(const void* p) {
  const rosflight_msgs_msg_dds__Barometer_* m = p;
  if (!(m->pressure > 50000 && m->pressure < 110000)) return "pressure outside (50, 110) kPa";
  if (!(m->altitude > -500 && m->altitude < 5000)) return "altitude outside (-500, 5000) m";
  if (!(m->temperature > 200 && m->temperature < 350)) return "temperature not in kelvin";
  return NULL;
}
static const builtin_interfaces_msg_dds__Time_* airspeed_stamp(const void* s) {
  return &((const rosflight_msgs_msg_dds__Airspeed_*)s)->header.stamp;
}
static const char* check_airspeed(const void* p) {
  const rosflight_msgs_msg_dds__Airspeed_* m = p;
  if (!(m->velocity > -10 && m->velocity < 60)) return "velocity outside (-10, 60) m/s";
  return NULL;
}
static const builtin_interfaces_msg_dds__Time_* mag_stamp(const void* s) {
  return &((const sensor_msgs_msg_dds__MagneticField_*)s)->header.stamp;
}
static const char* check_mag(const void* p) {
  const geometry_msgs_msg_dds__Vector3_* b = &((const sensor_msgs_msg_dds__MagneticField_*)p)->magnetic_field;
  const double n = sqrt(b->x * b->x + b->y * b->y + b->z * b->z);
  if (!(n > 1e-6 && n < 1e-4)) return "|magnetic_field| outside (1, 100) uT: not tesla";
  return NULL;
}
static const builtin_interfaces_msg_dds__Time_* status_stamp(const void* s) {
  return &((const rosflight_msgs_msg_dds__Status_*)s)->header.stamp;
}
static const char* check_status(const void* p) {
  const rosflight_msgs_msg_dds__Status_* m = p;
  if (m->num_errors < 0) return "num_errors < 0";
  return NULL;
}
static const builtin_interfaces_msg_dds__Time_* clock_stamp(const void* s) { return &((const rosgraph_msgs_msg_dds__Clock_*)s)->clock; }

#define REL DDS_RELIABILITY_RELIABLE
#define BE DDS_RELIABILITY_BEST_EFFORT
#define VOL DDS_DURABILITY_VOLATILE
#define TL DDS_DURABILITY_TRANSIENT_LOCAL
/* designated initializers: the results start zeroed */
#define TOPIC(n, d, rel, dur, dep, src, chk, st, min)                                                                    \
  {                                                                                                                      \
    .name = n, .desc = d, .reliability = rel, .durability = dur, .depth = dep, .source = src, .check = chk, .stamp = st, \
    .min_samples = min                                                                                                   \
  }
static topic_t topics[] = {
    TOPIC("rt/tern/estimated_state", &rosplane_msgs_msg_dds__State__desc, REL, VOL, 10, "rosplane_gcs rviz_waypoint_publisher.cpp",
          check_state, state_stamp, 20),
    TOPIC("rt/tern/waypoint_path", &rosplane_msgs_msg_dds__Waypoint__desc, REL, TL, 20, "rosplane_gcs rviz_waypoint_publisher.cpp",
          check_waypoint, waypoint_stamp, 2),
    TOPIC("rt/tern/imu/data", &sensor_msgs_msg_dds__Imu__desc, REL, VOL, 10, "rosplane estimator_ros.cpp", check_imu, imu_stamp, 20),
    TOPIC("rt/tern/gnss", &rosflight_msgs_msg_dds__GNSS__desc, REL, VOL, 10, "rosplane estimator_ros.cpp", check_gnss, gnss_stamp, 3),
    TOPIC("rt/tern/baro", &rosflight_msgs_msg_dds__Barometer__desc, REL, VOL, 10, "rosplane estimator_ros.cpp", check_baro, baro_stamp, 10),
    TOPIC("rt/tern/airspeed", &rosflight_msgs_msg_dds__Airspeed__desc, REL, VOL, 10, "rosplane estimator_ros.cpp", check_airspeed,
          airspeed_stamp, 10),
    TOPIC("rt/tern/magnetometer", &sensor_msgs_msg_dds__MagneticField__desc, REL, VOL, 10, "rosplane estimator_ros.cpp", check_mag,
          mag_stamp, 5),
    TOPIC("rt/tern/status", &rosflight_msgs_msg_dds__Status__desc, REL, VOL, 10, "rosplane estimator_ros.cpp", check_status, status_stamp,
          3),
    TOPIC("rt/clock", &rosgraph_msgs_msg_dds__Clock__desc, BE, VOL, 1, "rclcpp TimeSource (ClockQoS)", NULL, clock_stamp, 100),
};
#define N_TOPICS (sizeof topics / sizeof topics[0])
#define CLOCK (N_TOPICS - 1)

static dds_entity_t make_reader(dds_entity_t pp, topic_t* t) {
  dds_qos_t* q = dds_create_qos();
  dds_qset_reliability(q, t->reliability, DDS_SECS(1));
  dds_qset_durability(q, t->durability);
  dds_qset_history(q, DDS_HISTORY_KEEP_LAST, t->depth);
  dds_entity_t topic = dds_create_topic(pp, t->desc, t->name, NULL, NULL);
  dds_entity_t r = topic < 0 ? topic : dds_create_reader(pp, topic, q, NULL);
  dds_delete_qos(q);
  return r;
}

static int all_matched(void) {
  for (size_t i = 0; i < N_TOPICS; ++i) {
    dds_subscription_matched_status_t s;
    if (dds_get_subscription_matched_status(topics[i].reader, &s) != DDS_RETCODE_OK || s.current_count == 0) return 0;
  }
  return 1;
}

/* Takes every available sample of `t`, checking each. */
static void drain(topic_t* t) {
  for (;;) {
    void* ptrs[1] = {t->sample};
    dds_sample_info_t info;
    if (dds_take(t->reader, ptrs, &info, 1, 1) != 1) return;
    if (info.valid_data) {
      const double s = seconds(t->stamp(t->sample));
      const char* why = t->check != NULL ? t->check(t->sample) : NULL;
      if (why != NULL && t->bad == NULL) t->bad = why;
      if (t->samples == 0)
        t->first_stamp = t->min_stamp = t->max_stamp = s;
      else if (s < t->last_stamp)
        ++t->stamps_back;
      t->min_stamp = s < t->min_stamp ? s : t->min_stamp;
      t->max_stamp = s > t->max_stamp ? s : t->max_stamp;
      t->last_stamp = s;
      ++t->samples;
    }
    dds_sample_free(t->sample, t->desc, DDS_FREE_CONTENTS);
    memset(t->sample, 0, t->desc->m_size); /* the next take must not free the same strings again */
  }
}

static int enough(void) {
  for (size_t i = 0; i < N_TOPICS; ++i)
    if (topics[i].samples < topics[i].min_samples) return 0;
  return topics[CLOCK].last_stamp - topics[CLOCK].first_stamp >= 2.0;
}

/* The verdict on one topic; 0 when it passes. */
static int verdict(const topic_t* t, const topic_t* clock) {
  dds_requested_incompatible_qos_status_t inc;
  dds_get_requested_incompatible_qos_status(t->reader, &inc);
  const char* why = NULL;
  if (inc.total_count > 0)
    why = "incompatible QoS";
  else if (t->samples < t->min_samples)
    why = "too few samples";
  else if (t->bad != NULL)
    why = t->bad;
  else if (t->stamps_back > 0)
    why = "stamps went backwards";
  else if (t != clock && t->min_samples > 2 && !(t->last_stamp > t->first_stamp))
    why = "stamps do not advance";
  else if (t->min_stamp < 0 || t->max_stamp > clock->last_stamp + 0.5)
    why = "stamps not in sim time (outside /clock's range)";
  printf("%-26s %-5s %-15s depth %-2d %5d samples, stamps %8.3f..%8.3f s  %s  [%s]\n", t->name, t->reliability == REL ? "rel" : "be",
         t->durability == TL ? "transient_local" : "volatile", t->depth, t->samples, t->min_stamp, t->max_stamp, why == NULL ? "OK" : why,
         t->source);
  return why == NULL ? 0 : 1;
}

int main(int argc, char** argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: %s DOMAIN\n", argv[0]);
    return 2;
  }
  const dds_entity_t pp = dds_create_participant((dds_domainid_t)atoi(argv[1]), NULL, NULL);
  if (pp < 0) return printf("FAILED: create participant\n"), 1;
  for (size_t i = 0; i < N_TOPICS; ++i) {
    topics[i].reader = make_reader(pp, &topics[i]);
    topics[i].sample = calloc(1, topics[i].desc->m_size);
    if (topics[i].reader < 0 || topics[i].sample == NULL) return printf("FAILED: reader of %s\n", topics[i].name), 1;
  }
  const dds_time_t match_end = dds_time() + MATCH_TIMEOUT;
  while (!all_matched() && dds_time() < match_end) dds_sleepfor(DDS_MSECS(20));
  const dds_time_t end = dds_time() + RUN_TIMEOUT;
  while (dds_time() < end) {
    for (size_t i = 0; i < N_TOPICS; ++i) drain(&topics[i]);
    if (enough()) break;
    dds_sleepfor(DDS_MSECS(10));
  }
  int failed = 0;
  for (size_t i = 0; i < N_TOPICS; ++i) failed += verdict(&topics[i], &topics[CLOCK]);
  const double advanced = topics[CLOCK].last_stamp - topics[CLOCK].first_stamp;
  printf("/clock advanced %.3f s of sim time\n", advanced);
  if (advanced < 2.0) ++failed, printf("FAILED: /clock advanced less than 2 s\n");
  for (size_t i = 0; i < N_TOPICS; ++i) free(topics[i].sample);
  dds_delete(pp);
  if (failed) printf("FAILED: %d checks\n", failed);
  return failed ? 1 : 0;
}
