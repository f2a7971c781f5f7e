#pragma once
// Decoding serialized ROS messages generically, driven by a parsed definition
// (ros_msg_definition.h): every numeric field becomes a value, named by its
// path with '.' between levels ("angular_velocity.x", "position.wheel_FL").
//
// - Arrays (fixed or variable) of at most Limits::max_array elements give one
//   value per element, named by index ("covariance.0"); longer arrays (camera
//   images, point clouds) are skipped whole.
// - Parallel arrays after a `string[] name` field (sensor_msgs/JointState) are
//   named by its entries when they have as many elements ("position.FL").
// - A quaternion (x, y, z, w) also gives roll, pitch, yaw (rad, ZYX).
// - time and duration give seconds; bool 0/1; strings are skipped.
//
// Encodings: ROS 1 (little-endian, packed, uint32 lengths) and CDR (ROS 2:
// encapsulation header, aligned fields, strings with their NUL).

#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "importers/ros_msg_definition.h"

namespace roverlab::io::ros {

// A message that does not match its definition (too short, too long, an
// array longer than the message). what() is one line.
class DecodeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// json: MCAP JSON messages, flattened by MessageLog (no definition needed).
enum class Encoding { ros1, cdr, json };

struct Limits {
  std::size_t max_array = 64;  // longer arrays are skipped whole
  // The channels one topic may make (values of one message, names a topic
  // collects): 64-element arrays nested four deep would make 16.7 million.
  std::size_t max_channels = 10'000;
};

// One decoded message. The values' names depend only on `lengths` and
// `labels`: a message shaped like the previous one reuses its names.
struct DecodedMessage {
  std::vector<double> values;
  std::vector<std::uint32_t> lengths;  // each variable-length array's length, in walk order
  // The entries of each `string[] name` field (and child_frame_id of an
  // array's elements), in walk order; kept from message to message, so that
  // labels_changed says whether this message's differ from the previous one
  // decoded into the same DecodedMessage (no allocation when they do not).
  std::vector<std::string> labels;
  std::size_t label_count = 0;
  bool labels_changed = true;
  // header.stamp in nanoseconds when the type starts with a std_msgs/Header
  // (and the stamp is not negative); -1 otherwise.
  std::int64_t header_stamp_ns = -1;
};

class Decoder {
 public:
  Decoder(Schema schema, Encoding encoding, Limits limits = {});

  // Throws DecodeError when the bytes do not match the definition.
  void decode(const std::uint8_t* data, std::size_t size, DecodedMessage& out) const;

  // The names of `message.values`, in order.
  std::vector<std::string> value_names(const DecodedMessage& message) const;

  const Schema& schema() const { return schema_; }
  bool has_header() const { return header_stamp_field_ >= 0; }

 private:
  class Walk;
  Schema schema_;
  Encoding encoding_;
  Limits limits_;
  std::vector<std::size_t> min_size_;  // fewest bytes a value of each type takes
  int header_stamp_field_ = -1;        // index of `stamp` in the root's Header
};

// Roll, pitch, yaw (ZYX, rad) of a unit quaternion; NaN for a zero one.
void quaternion_to_rpy(double x, double y, double z, double w, double& roll, double& pitch, double& yaw);

}  // namespace roverlab::io::ros
