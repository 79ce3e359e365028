#include "ros/scene_msgs.hpp"

#include <map>
#include <utility>

#include "ros/cdr_writer.hpp"

namespace tern::core {

namespace {

// The .msg fields (constants included) of each type, by its short name "pkg/Type".
const std::map<std::string, std::string>& msg_texts() {
  static const std::map<std::string, std::string> texts = {
      {"builtin_interfaces/Time", "int32 sec\nuint32 nanosec\n"},
      {"builtin_interfaces/Duration", "int32 sec\nuint32 nanosec\n"},
      {"std_msgs/Header", "builtin_interfaces/Time stamp\nstring frame_id\n"},
      {"std_msgs/ColorRGBA", "float32 r\nfloat32 g\nfloat32 b\nfloat32 a\n"},
      {"geometry_msgs/Vector3", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/Point", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/Quaternion", "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n"},
      {"geometry_msgs/Pose", "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n"},
      {"geometry_msgs/Transform", "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n"},
      {"geometry_msgs/TransformStamped", "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform\n"},
      {"tf2_msgs/TFMessage", "geometry_msgs/TransformStamped[] transforms\n"},
      {"sensor_msgs/CompressedImage", "std_msgs/Header header\nstring format\nuint8[] data\n"},
      {"visualization_msgs/UVCoordinate", "float32 u\nfloat32 v\n"},
      {"visualization_msgs/MeshFile", "string filename\nuint8[] data\n"},
      {"visualization_msgs/Marker",
       "int32 ARROW=0\nint32 CUBE=1\nint32 SPHERE=2\nint32 CYLINDER=3\nint32 LINE_STRIP=4\nint32 LINE_LIST=5\n"
       "int32 CUBE_LIST=6\nint32 SPHERE_LIST=7\nint32 POINTS=8\nint32 TEXT_VIEW_FACING=9\nint32 MESH_RESOURCE=10\n"
       "int32 TRIANGLE_LIST=11\nint32 ARROW_STRIP=12\n"
       "int32 ADD=0\nint32 MODIFY=0\nint32 DELETE=2\nint32 DELETEALL=3\n"
       "std_msgs/Header header\nstring ns\nint32 id\nint32 type\nint32 action\ngeometry_msgs/Pose pose\n"
       "geometry_msgs/Vector3 scale\nstd_msgs/ColorRGBA color\nbuiltin_interfaces/Duration lifetime\nbool frame_locked\n"
       "geometry_msgs/Point[] points\nstd_msgs/ColorRGBA[] colors\nstring texture_resource\n"
       "sensor_msgs/CompressedImage texture\nvisualization_msgs/UVCoordinate[] uv_coordinates\nstring text\n"
       "string mesh_resource\nvisualization_msgs/MeshFile mesh_file\nbool mesh_use_embedded_materials\n"},
      {"visualization_msgs/MarkerArray", "visualization_msgs/Marker[] markers\n"},
  };
  return texts;
}

// `root`'s text, then each type in `deps` after its separator (rosbag2's ros2msg schema).
std::string schema(const std::string& root, const std::vector<std::string>& deps) {
  std::string s = msg_texts().at(root);
  for (const std::string& d : deps) s += std::string(80, '=') + "\nMSG: " + d + "\n" + msg_texts().at(d);
  return s;
}

void put_header(CdrWriter& w, Nanos stamp, const std::string& frame_id) {
  // builtin_interfaces/Time: whole seconds and the nanoseconds after them (flight time >= 0)
  w.i32(static_cast<std::int32_t>(stamp / 1'000'000'000));
  w.u32(static_cast<std::uint32_t>(stamp % 1'000'000'000));
  w.string(frame_id);
}

void put_xyz(CdrWriter& w, const Eigen::Vector3d& v) {
  w.f64(v.x());
  w.f64(v.y());
  w.f64(v.z());
}

void put_quaternion(CdrWriter& w, const Eigen::Quaterniond& q) {
  w.f64(q.x());
  w.f64(q.y());
  w.f64(q.z());
  w.f64(q.w());
}

void put_marker(CdrWriter& w, const RosMarker& m) {
  put_header(w, m.stamp, m.frame_id);
  w.string(m.ns);
  w.i32(m.id);
  w.i32(m.type);
  w.i32(0);  // ADD
  put_xyz(w, m.position);
  put_quaternion(w, m.orientation);
  put_xyz(w, m.scale);
  for (float c : m.color) w.f32(c);
  w.i32(0);  // lifetime: 0, until replaced
  w.u32(0);
  w.boolean(m.frame_locked);
  w.count(m.points.size());
  for (const auto& p : m.points) put_xyz(w, p);
  w.count(0);            // colors: every point in `color`
  w.string("");          // texture_resource
  put_header(w, 0, "");  // texture: none
  w.string("");
  w.count(0);
  w.count(0);    // uv_coordinates
  w.string("");  // text
  w.string("");  // mesh_resource
  w.string("");  // mesh_file: none
  w.count(0);
  w.boolean(false);  // mesh_use_embedded_materials
}

}  // namespace

std::string tf_message_schema() {
  return schema("tf2_msgs/TFMessage", {"geometry_msgs/TransformStamped", "std_msgs/Header", "builtin_interfaces/Time",
                                       "geometry_msgs/Transform", "geometry_msgs/Vector3", "geometry_msgs/Quaternion"});
}

std::string marker_array_schema() {
  return schema("visualization_msgs/MarkerArray",
                {"visualization_msgs/Marker", "std_msgs/Header", "builtin_interfaces/Time", "geometry_msgs/Pose", "geometry_msgs/Point",
                 "geometry_msgs/Quaternion", "geometry_msgs/Vector3", "std_msgs/ColorRGBA", "builtin_interfaces/Duration",
                 "sensor_msgs/CompressedImage", "visualization_msgs/UVCoordinate", "visualization_msgs/MeshFile"});
}

void encode_tf_message(const std::vector<RosTransform>& transforms, std::string& out) {
  CdrWriter w(out);
  w.count(transforms.size());
  for (const RosTransform& t : transforms) {
    put_header(w, t.stamp, t.parent);
    w.string(t.child);
    put_xyz(w, t.translation);
    put_quaternion(w, t.rotation);
  }
}

void encode_marker_array(const std::vector<RosMarker>& markers, std::string& out) {
  CdrWriter w(out);
  w.count(markers.size());
  for (const RosMarker& m : markers) put_marker(w, m);
}

}  // namespace tern::core
