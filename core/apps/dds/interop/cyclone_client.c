/* core/apps/dds/interop/cyclone_client.c: a ROS 2 tool's view of tern, built on Eclipse Cyclone DDS
 * (the other DDS that ROS 2 ships) with types from ros2_types.idl (idlc), not tern's code.
 * Against a running `tern fly --dds` on DDS domain argv[1], namespace argv[2] (default "tern"; a
 * multi-vehicle mission's vehicle name), loopback only:
 *   1. discovers the nodes on ros_discovery_info (rmw_dds_common ParticipantEntitiesInfo);
 *   2. reads rt/<namespace>/state as rosplane_msgs/msg/State;
 *   3. sets ctl's parameter kp through rcl_interfaces set_parameters and sees the change on
 *      rt/parameter_events; describes it through describe_parameters;
 *   4. adds a waypoint with ROSplane's add_waypoint (rosplane_msgs/srv/AddWaypoint).
 * Requests and replies follow the ROS 2 topic names (rq/<service>Request, rr/<service>Reply);
 * Cyclone cannot write the related_sample_identity that rmw_fastrtps clients add, so it takes
 * the one reply on the reply topic (it is the only client). Prints a transcript; exit 0 when
 * every step succeeded, 1 with the failing step otherwise. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <dds/dds.h>
#include <dds/version.h>

#include "ros2_types.h"

#define TIMEOUT DDS_SECS(30)

static const char* ns = "tern"; /* the vehicle's namespace */

/* "<ns>/<rest>" (static buffer: one use at a time) */
static const char* in_ns(const char* fmt_rest) {
  static char buf[256];
  snprintf(buf, sizeof buf, fmt_rest, ns);
  return buf;
}

static int fail(const char* step) {
  printf("FAILED: %s\n", step);
  return 1;
}

static dds_qos_t* qos(dds_reliability_kind_t rel, dds_durability_kind_t dur, int32_t depth) {
  dds_qos_t* q = dds_create_qos();
  dds_qset_reliability(q, rel, DDS_SECS(1));
  dds_qset_durability(q, dur);
  dds_qset_history(q, depth > 0 ? DDS_HISTORY_KEEP_LAST : DDS_HISTORY_KEEP_ALL, depth > 0 ? depth : 0);
  return q;
}

static dds_entity_t reader(dds_entity_t pp, const dds_topic_descriptor_t* desc, const char* name, dds_qos_t* q) {
  dds_entity_t t = dds_create_topic(pp, desc, name, NULL, NULL);
  dds_entity_t r = dds_create_reader(pp, t, q, NULL);
  dds_delete_qos(q);
  return r;
}

static dds_entity_t writer(dds_entity_t pp, const dds_topic_descriptor_t* desc, const char* name, dds_qos_t* q) {
  dds_entity_t t = dds_create_topic(pp, desc, name, NULL, NULL);
  dds_entity_t w = dds_create_writer(pp, t, q, NULL);
  dds_delete_qos(q);
  return w;
}

/* Takes one valid sample into `sample` within TIMEOUT; 0 on success. */
static int take_one(dds_entity_t r, void* sample) {
  const dds_time_t end = dds_time() + TIMEOUT;
  while (dds_time() < end) {
    void* ptrs[1] = {sample};
    dds_sample_info_t info;
    if (dds_take(r, ptrs, &info, 1, 1) == 1 && info.valid_data) return 0;
    dds_sleepfor(DDS_MSECS(20));
  }
  return -1;
}

/* Waits until `w` has matched a reader and `r` a writer (the vehicle's service). */
static int wait_matched(dds_entity_t w, dds_entity_t r) {
  const dds_time_t end = dds_time() + TIMEOUT;
  while (dds_time() < end) {
    dds_publication_matched_status_t ps;
    dds_subscription_matched_status_t ss;
    dds_get_publication_matched_status(w, &ps);
    dds_get_subscription_matched_status(r, &ss);
    if (ps.current_count > 0 && ss.current_count > 0) return 0;
    dds_sleepfor(DDS_MSECS(20));
  }
  return -1;
}

/* One request/reply: rq/<service>Request, rr/<service>Reply. */
static int call(dds_entity_t pp, const char* service, const dds_topic_descriptor_t* rq_desc, const void* rq,
                const dds_topic_descriptor_t* rs_desc, void* rs) {
  char rq_name[256], rs_name[256];
  snprintf(rq_name, sizeof rq_name, "rq/%sRequest", service);
  snprintf(rs_name, sizeof rs_name, "rr/%sReply", service);
  dds_entity_t w = writer(pp, rq_desc, rq_name, qos(DDS_RELIABILITY_RELIABLE, DDS_DURABILITY_VOLATILE, 10));
  dds_entity_t r = reader(pp, rs_desc, rs_name, qos(DDS_RELIABILITY_RELIABLE, DDS_DURABILITY_VOLATILE, 10));
  if (w < 0 || r < 0 || wait_matched(w, r) != 0) return -1;
  if (dds_write(w, rq) != DDS_RETCODE_OK) return -1;
  return take_one(r, rs);
}

static int discover(dds_entity_t pp) {
  dds_entity_t r = reader(pp, &rmw_dds_common_msg_dds__ParticipantEntitiesInfo__desc, "ros_discovery_info",
                          qos(DDS_RELIABILITY_RELIABLE, DDS_DURABILITY_TRANSIENT_LOCAL, 0));
  rmw_dds_common_msg_dds__ParticipantEntitiesInfo_ info;
  memset(&info, 0, sizeof info);
  int found = 0;
  while (!found && take_one(r, &info) == 0) {
    printf("ros_discovery_info:");
    for (uint32_t i = 0; i < info.node_entities_info_seq._length; ++i) {
      const rmw_dds_common_msg_dds__NodeEntitiesInfo_* n = &info.node_entities_info_seq._buffer[i];
      printf(" %s/%s", n->node_namespace, n->node_name);
      found = found || (strcmp(n->node_namespace, in_ns("/%s")) == 0 && strcmp(n->node_name, "ctl") == 0);
    }
    printf("\n");
    dds_sample_free(&info, &rmw_dds_common_msg_dds__ParticipantEntitiesInfo__desc, DDS_FREE_CONTENTS);
    memset(&info, 0, sizeof info);
  }
  return found ? 0 : -1;
}

static int read_state(dds_entity_t pp) {
  dds_entity_t r =
      reader(pp, &rosplane_msgs_msg_dds__State__desc, in_ns("rt/%s/state"), qos(DDS_RELIABILITY_BEST_EFFORT, DDS_DURABILITY_VOLATILE, 1));
  rosplane_msgs_msg_dds__State_ s;
  memset(&s, 0, sizeof s);
  if (take_one(r, &s) != 0) return -1;
  printf("rt/%s/state: stamp %d.%09u p_d %.3f va %.3f quat.w %.4f\n", ns, s.header.stamp.sec, s.header.stamp.nanosec, s.p_d, s.va,
         s.quat.w);
  const int ok = s.va > 0 ? 0 : -1;
  dds_sample_free(&s, &rosplane_msgs_msg_dds__State__desc, DDS_FREE_CONTENTS);
  return ok;
}

static int set_parameter(dds_entity_t pp) {
  dds_entity_t ev = reader(pp, &rcl_interfaces_msg_dds__ParameterEvent__desc, "rt/parameter_events",
                           qos(DDS_RELIABILITY_RELIABLE, DDS_DURABILITY_VOLATILE, 100));
  rcl_interfaces_msg_dds__Parameter_ p;
  memset(&p, 0, sizeof p);
  p.name = "kp";
  p.value.type = 3; /* PARAMETER_DOUBLE */
  p.value.double_value = 0.125;
  p.value.string_value = "";
  rcl_interfaces_srv_dds__SetParameters_Request_ rq = {.parameters = {1, 1, &p, false}};
  rcl_interfaces_srv_dds__SetParameters_Response_ rs;
  memset(&rs, 0, sizeof rs);
  dds_sleepfor(DDS_MSECS(500)); /* the event reader matches the vehicle's writer */
  if (call(pp, in_ns("%s/ctl/set_parameters"), &rcl_interfaces_srv_dds__SetParameters_Request__desc, &rq,
           &rcl_interfaces_srv_dds__SetParameters_Response__desc, &rs) != 0 ||
      rs.results._length != 1)
    return -1;
  printf("set_parameters /%s/ctl kp 0.125: successful %d reason '%s'\n", ns, rs.results._buffer[0].successful,
         rs.results._buffer[0].reason);
  const int successful = rs.results._buffer[0].successful;
  dds_sample_free(&rs, &rcl_interfaces_srv_dds__SetParameters_Response__desc, DDS_FREE_CONTENTS);
  if (!successful) return -1;
  rcl_interfaces_msg_dds__ParameterEvent_ e;
  memset(&e, 0, sizeof e);
  if (take_one(ev, &e) != 0 || e.changed_parameters._length != 1) return -1;
  printf("rt/parameter_events: node %s changed %s = %g\n", e.node, e.changed_parameters._buffer[0].name,
         e.changed_parameters._buffer[0].value.double_value);
  const int ok = strcmp(e.node, in_ns("/%s/ctl")) == 0 && e.changed_parameters._buffer[0].value.double_value == 0.125 ? 0 : -1;
  dds_sample_free(&e, &rcl_interfaces_msg_dds__ParameterEvent__desc, DDS_FREE_CONTENTS);
  return ok;
}

static int describe_parameter(dds_entity_t pp) {
  char* names[1] = {"kp"};
  rcl_interfaces_srv_dds__DescribeParameters_Request_ rq = {.names = {1, 1, names, false}};
  rcl_interfaces_srv_dds__DescribeParameters_Response_ rs;
  memset(&rs, 0, sizeof rs);
  if (call(pp, in_ns("%s/ctl/describe_parameters"), &rcl_interfaces_srv_dds__DescribeParameters_Request__desc, &rq,
           &rcl_interfaces_srv_dds__DescribeParameters_Response__desc, &rs) != 0 ||
      rs.descriptors._length != 1)
    return -1;
  const rcl_interfaces_msg_dds__ParameterDescriptor_* d = &rs.descriptors._buffer[0];
  printf("describe_parameters /%s/ctl kp: type %u description '%s' constraints '%s' read_only %d", ns, d->type, d->description,
         d->additional_constraints, d->read_only);
  if (d->floating_point_range._length == 1)
    printf(" range [%g, %g]", d->floating_point_range._buffer[0].from_value, d->floating_point_range._buffer[0].to_value);
  printf("\n");
  const int ok = d->type == 3 && d->floating_point_range._length == 1 ? 0 : -1;
  dds_sample_free(&rs, &rcl_interfaces_srv_dds__DescribeParameters_Response__desc, DDS_FREE_CONTENTS);
  return ok;
}

static int add_waypoint(dds_entity_t pp) {
  rosplane_msgs_srv_dds__AddWaypoint_Request_ rq = {.w = {120.0f, -80.0f, -50.0f}, .va_d = 17.0f, .publish_now = true};
  rosplane_msgs_srv_dds__AddWaypoint_Response_ rs;
  memset(&rs, 0, sizeof rs);
  if (call(pp, in_ns("%s/add_waypoint"), &rosplane_msgs_srv_dds__AddWaypoint_Request__desc, &rq,
           &rosplane_msgs_srv_dds__AddWaypoint_Response__desc, &rs) != 0)
    return -1;
  printf("add_waypoint [120, -80, -50] va_d 17: success %d message '%s'\n", rs.success, rs.message);
  const int ok = rs.success ? 0 : -1;
  dds_sample_free(&rs, &rosplane_msgs_srv_dds__AddWaypoint_Response__desc, DDS_FREE_CONTENTS);
  return ok;
}

int main(int argc, char** argv) {
  if (argc != 2 && argc != 3) {
    fprintf(stderr, "usage: %s DOMAIN [NAMESPACE]\n", argv[0]);
    return 2;
  }
  if (argc == 3) ns = argv[2];
  const dds_entity_t pp = dds_create_participant((dds_domainid_t)atoi(argv[1]), NULL, NULL);
  if (pp < 0) return fail("create a Cyclone DDS participant");
  int rc = 0;
  if (discover(pp) != 0)
    rc = fail("discover node ctl in the namespace on ros_discovery_info");
  else if (read_state(pp) != 0)
    rc = fail("read rt/<namespace>/state as rosplane_msgs/msg/State");
  else if (describe_parameter(pp) != 0)
    rc = fail("describe <namespace>/ctl kp (rcl_interfaces describe_parameters)");
  else if (set_parameter(pp) != 0)
    rc = fail("set <namespace>/ctl kp and see it on rt/parameter_events");
  else if (add_waypoint(pp) != 0)
    rc = fail("add a waypoint (rosplane_msgs/srv/AddWaypoint)");
  dds_delete(pp);
  if (rc == 0) printf("OK: Cyclone DDS %s client drove tern's /%s\n", DDS_VERSION, ns);
  return rc;
}
