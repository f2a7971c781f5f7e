#pragma once
// The ROS message-definition language (.msg text, as a ROS 1 bag's connection
// header and an MCAP `ros1msg` / `ros2msg` schema carry it): the root type's
// fields, then each nested type after a line of '=' and a `MSG: pkg/Type`
// line. Parsed into a schema that ros_msg_decoder.h walks, so any message type
// is read without compile-time message headers.

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace roverlab::io::ros {

// A definition that cannot be parsed or refers to a type it does not define.
class DefinitionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class Primitive {
  boolean,
  int8,
  uint8,
  int16,
  uint16,
  int32,
  uint32,
  int64,
  uint64,
  float32,
  float64,
  string,
  time,      // ROS 1: uint32 sec, uint32 nsec
  duration,  // ROS 1: int32 sec, int32 nsec
  message,   // a nested type (Field::nested)
};

// Which dialect the text is: ROS 1 (`Header` is std_msgs/Header, `time` and
// `duration` are builtins) or ROS 2 (bounded strings and arrays, default
// values, builtin_interfaces types).
enum class Dialect { ros1, ros2 };

struct Field {
  std::string name;
  Primitive type = Primitive::float64;
  std::size_t nested = 0;  // index into Schema::types when type == message
  bool is_array = false;
  std::size_t fixed_length = 0;  // > 0: a fixed-length array T[N]
};

struct MessageType {
  std::string name;  // "sensor_msgs/Imu" (ROS 2's "pkg/msg/Type" is stored as "pkg/Type")
  std::vector<Field> fields;
  // Four float64 fields x, y, z, w: also decoded as roll, pitch, yaw.
  bool is_quaternion = false;
  // Index of a `string[] name` field whose entries label the parallel
  // numeric arrays after it (sensor_msgs/JointState); -1 when none.
  int label_field = -1;
  // Index of a `string child_frame_id` field (geometry_msgs/TransformStamped):
  // in an array of this type (tf2_msgs/TFMessage) it names each element, as
  // `name` entries do. -1 when none, or when the type holds other labels.
  int frame_field = -1;
  // The type or a type inside it has a label_field or a frame_field.
  bool has_labels = false;
};

struct Schema {
  std::vector<MessageType> types;  // types[0] is the root
  Dialect dialect = Dialect::ros1;
};

// Parses `text`, the definition of `root_type` ("sensor_msgs/Imu" or
// "sensor_msgs/msg/Imu"). Constants are ignored. Throws DefinitionError for a
// malformed line, a type the text does not define, or a type that contains
// itself.
Schema parse_definition(const std::string& root_type, const std::string& text, Dialect dialect = Dialect::ros1);

}  // namespace roverlab::io::ros
