#pragma once
// A message of any type for the ROS library's own bag writer (rosbag::Bag):
// its type name, definition text and serialized bytes given at run time, as
// topic_tools::ShapeShifter does. Tests write damaged messages with it; the
// well-formed ones come from the message headers ROS generates.

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <ros/message_traits.h>
#include <ros/serialization.h>

namespace roverlab::test {

struct RawRosMessage {
  std::string type;
  std::string definition;
  std::vector<std::uint8_t> bytes;
  std::string md5 = "*";
};

}  // namespace roverlab::test

namespace ros {
namespace message_traits {
template <>
struct MD5Sum<roverlab::test::RawRosMessage> {
  static const char* value(const roverlab::test::RawRosMessage& m) { return m.md5.c_str(); }
  static const char* value() { return "*"; }
};
template <>
struct DataType<roverlab::test::RawRosMessage> {
  static const char* value(const roverlab::test::RawRosMessage& m) { return m.type.c_str(); }
  static const char* value() { return "*"; }
};
template <>
struct Definition<roverlab::test::RawRosMessage> {
  static const char* value(const roverlab::test::RawRosMessage& m) { return m.definition.c_str(); }
  static const char* value() { return ""; }
};
}  // namespace message_traits
namespace serialization {
template <>
struct Serializer<roverlab::test::RawRosMessage> {
  template <typename Stream>
  static void write(Stream& stream, const roverlab::test::RawRosMessage& m) {
    if (!m.bytes.empty())
      std::memcpy(stream.advance(static_cast<std::uint32_t>(m.bytes.size())), m.bytes.data(), m.bytes.size());
  }
  static std::uint32_t serializedLength(const roverlab::test::RawRosMessage& m) {
    return static_cast<std::uint32_t>(m.bytes.size());
  }
};
}  // namespace serialization
}  // namespace ros
