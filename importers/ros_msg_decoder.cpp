#include "importers/ros_msg_decoder.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace roverlab::io::ros {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the decoders read little-endian data in place");

namespace {

constexpr std::size_t kHuge = std::size_t{1} << 40;  // saturated minimum sizes

std::size_t primitive_size(Primitive p) {
  switch (p) {
    case Primitive::boolean:
    case Primitive::int8:
    case Primitive::uint8:
      return 1;
    case Primitive::int16:
    case Primitive::uint16:
      return 2;
    case Primitive::int32:
    case Primitive::uint32:
    case Primitive::float32:
      return 4;
    case Primitive::int64:
    case Primitive::uint64:
    case Primitive::float64:
    case Primitive::time:
    case Primitive::duration:
      return 8;
    case Primitive::string:
      return 4;  // the length; the characters follow
    case Primitive::message:
      return 0;
  }
  return 0;
}

std::size_t saturated_product(std::size_t a, std::size_t b) {
  if (a == 0 || b == 0) return 0;
  return a > kHuge / b ? kHuge : a * b;
}

// A label's character as a channel name may hold it.
char sanitized_char(char c) { return c == '/' || c == '\0' || c == '\n' || c == '\r' ? '_' : c; }

template <class T>
T swapped(T v) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));
  std::reverse(bytes, bytes + sizeof(T));
  std::memcpy(&v, bytes, sizeof(T));
  return v;
}

}  // namespace

void quaternion_to_rpy(double x, double y, double z, double w, double& roll, double& pitch, double& yaw) {
  const double norm = std::sqrt(x * x + y * y + z * z + w * w);
  if (!(norm > 0.0) || !std::isfinite(norm)) {
    roll = pitch = yaw = std::nan("");
    return;
  }
  x /= norm;
  y /= norm;
  z /= norm;
  w /= norm;
  roll = std::atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y));
  pitch = std::asin(std::clamp(2.0 * (w * y - z * x), -1.0, 1.0));
  yaw = std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
}

// The bytes of one message, read in walk order.
class Decoder::Walk {
 public:
  Walk(const Decoder& decoder, const std::uint8_t* data, std::size_t size, DecodedMessage& out)
      : d_(decoder), data_(data), size_(size), out_(out) {
    if (d_.encoding_ == Encoding::cdr) {
      if (size < 4) fail();
      // Encapsulation: 00 00 big-endian CDR, 00 01 little-endian CDR.
      if (data[0] != 0 || (data[1] != 0 && data[1] != 1)) {
        throw DecodeError("unsupported CDR representation " + std::to_string(data[0]) + " " + std::to_string(data[1]));
      }
      swap_ = data[1] == 0;
      pos_ = origin_ = 4;
    }
  }

  void run() {
    message(0, true, true);
    const std::size_t left = size_ - pos_;
    // CDR pads a message to a multiple of 4 (or 8); ROS 1 has no padding.
    if (left > (d_.encoding_ == Encoding::cdr ? 7U : 0U)) {
      throw DecodeError("message of " + std::to_string(size_) + " bytes is longer than its definition (" +
                        d_.schema_.types[0].name + ") needs: " + std::to_string(left) + " bytes left over");
    }
  }

 private:
  // The next label, sanitized: compared with the previous message's in place.
  void label(std::string_view raw) {
    std::vector<std::string>& labels = out_.labels;
    const std::size_t i = out_.label_count++;
    if (i < labels.size() && labels[i].size() == raw.size()) {
      bool same = true;
      for (std::size_t c = 0; same && c < raw.size(); ++c) same = labels[i][c] == sanitized_char(raw[c]);
      if (same) return;
    }
    if (i >= labels.size()) labels.emplace_back();
    labels[i].assign(raw);
    for (char& c : labels[i]) c = sanitized_char(c);
    out_.labels_changed = true;
  }

  // A message of more values than a topic may have channels is refused
  // before it is decoded whole (nested arrays multiply).
  void check_value_count() const {
    if (out_.values.size() > d_.limits_.max_channels) {
      throw DecodeError("more than " + std::to_string(d_.limits_.max_channels) +
                        " values in one message (the cap on a topic's channels)");
    }
  }

  [[noreturn]] void fail() const {
    throw DecodeError("message of " + std::to_string(size_) + " bytes is shorter than its definition (" +
                      d_.schema_.types[0].name + ") needs");
  }

  void align(std::size_t n) {
    if (d_.encoding_ != Encoding::cdr || n <= 1) return;
    const std::size_t pad = (n - (pos_ - origin_) % n) % n;
    need(pad);
    pos_ += pad;
  }
  void need(std::size_t n) const {
    if (n > size_ - pos_) fail();
  }

  template <class T>
  T read() {
    align(sizeof(T));
    need(sizeof(T));
    T v;
    std::memcpy(&v, data_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    return swap_ ? swapped(v) : v;
  }

  std::uint32_t read_length() { return read<std::uint32_t>(); }

  // seconds and nanoseconds of a time or duration
  void read_time(Primitive p, std::int64_t& sec, std::int64_t& nsec) {
    if (d_.encoding_ == Encoding::cdr) {
      sec = read<std::int32_t>();
      nsec = read<std::uint32_t>();
    } else if (p == Primitive::time) {
      sec = read<std::uint32_t>();
      nsec = read<std::uint32_t>();
    } else {
      sec = read<std::int32_t>();
      nsec = read<std::int32_t>();
    }
  }

  double number(Primitive p) {
    switch (p) {
      case Primitive::boolean:
        return read<std::uint8_t>() != 0 ? 1.0 : 0.0;
      case Primitive::int8:
        return read<std::int8_t>();
      case Primitive::uint8:
        return read<std::uint8_t>();
      case Primitive::int16:
        return read<std::int16_t>();
      case Primitive::uint16:
        return read<std::uint16_t>();
      case Primitive::int32:
        return read<std::int32_t>();
      case Primitive::uint32:
        return read<std::uint32_t>();
      case Primitive::int64:
        return static_cast<double>(read<std::int64_t>());
      case Primitive::uint64:
        return static_cast<double>(read<std::uint64_t>());
      case Primitive::float32:
        return read<float>();
      case Primitive::float64:
        return read<double>();
      case Primitive::time:
      case Primitive::duration: {
        std::int64_t sec = 0;
        std::int64_t nsec = 0;
        read_time(p, sec, nsec);
        return static_cast<double>(sec) + static_cast<double>(nsec) * 1e-9;
      }
      case Primitive::string:
      case Primitive::message:
        break;
    }
    return 0.0;
  }

  std::string_view string() {
    const std::uint32_t n = read_length();
    need(n);
    std::string_view s(reinterpret_cast<const char*>(data_ + pos_), n);
    pos_ += n;
    if (d_.encoding_ == Encoding::cdr && !s.empty() && s.back() == '\0') s.remove_suffix(1);
    return s;
  }

  std::size_t element_min_size(const Field& f) const {
    return f.type == Primitive::message ? d_.min_size_[f.nested] : primitive_size(f.type);
  }

  void scalar(const Field& f, bool emit, bool stamp) {
    if (f.type == Primitive::message) {
      message(f.nested, emit, false);
    } else if (f.type == Primitive::string) {
      (void)string();
    } else if (stamp) {
      std::int64_t sec = 0;
      std::int64_t nsec = 0;
      read_time(f.type, sec, nsec);
      if (emit) out_.values.push_back(static_cast<double>(sec) + static_cast<double>(nsec) * 1e-9);
      if (sec >= 0 && nsec >= 0) out_.header_stamp_ns = sec * 1'000'000'000 + nsec;
    } else {
      const double v = number(f.type);
      if (emit) out_.values.push_back(v);
    }
  }

  void array(const MessageType& type, std::size_t k, bool emit) {
    const Field& f = type.fields[k];
    const bool variable = f.fixed_length == 0;
    const std::size_t n = variable ? read_length() : f.fixed_length;
    // No length may claim more than the message holds (a 10 GB length field).
    if (saturated_product(n, element_min_size(f)) > size_ - pos_) fail();
    const bool take = emit && n <= d_.limits_.max_array;
    if (emit && variable) out_.lengths.push_back(static_cast<std::uint32_t>(n));
    if (f.type == Primitive::string) {
      const bool labels = take && static_cast<int>(k) == type.label_field;
      for (std::size_t i = 0; i < n; ++i) {
        const std::string_view s = string();
        if (labels) label(s);
      }
    } else if (f.type == Primitive::message) {
      if (!take && d_.min_size_[f.nested] == 0) return;  // nothing to read, nothing to keep
      const bool frames = take && d_.schema_.types[f.nested].frame_field >= 0;
      for (std::size_t i = 0; i < n; ++i) {
        message(f.nested, take, false, frames);
        if (take) check_value_count();
      }
    } else if (take) {
      for (std::size_t i = 0; i < n; ++i) out_.values.push_back(number(f.type));
      check_value_count();
    } else if (n > 0) {
      const std::size_t bytes = n * primitive_size(f.type);  // bounded above
      align(f.type == Primitive::time || f.type == Primitive::duration ? 4 : primitive_size(f.type));
      need(bytes);
      pos_ += bytes;
    }
  }

  // frame: the message is an element of an array its child_frame_id labels.
  void message(std::size_t index, bool emit, bool root, bool frame = false) {
    const MessageType& type = d_.schema_.types[index];
    for (std::size_t k = 0; k < type.fields.size(); ++k) {
      const Field& f = type.fields[k];
      if (f.is_array) {
        array(type, k, emit);
      } else if (frame && static_cast<int>(k) == type.frame_field) {
        std::string_view id = string();
        while (!id.empty() && id.front() == '/') id.remove_prefix(1);  // tf's "/base_link" is tf2's "base_link"
        label(id);
      } else if (root && k == 0 && d_.header_stamp_field_ >= 0) {
        header(f.nested, emit);
      } else {
        scalar(f, emit, false);
      }
    }
    if (emit && type.is_quaternion) {
      const double* q = out_.values.data() + out_.values.size() - 4;
      double r = 0.0;
      double p = 0.0;
      double y = 0.0;
      quaternion_to_rpy(q[0], q[1], q[2], q[3], r, p, y);
      out_.values.insert(out_.values.end(), {r, p, y});
    }
  }

  void header(std::size_t index, bool emit) {
    const MessageType& type = d_.schema_.types[index];
    for (std::size_t k = 0; k < type.fields.size(); ++k) {
      if (type.fields[k].is_array) {
        array(type, k, emit);
      } else {
        scalar(type.fields[k], emit, static_cast<int>(k) == d_.header_stamp_field_);
      }
    }
  }

  const Decoder& d_;
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  std::size_t origin_ = 0;
  bool swap_ = false;
  DecodedMessage& out_;
};

namespace {

// The names of the values, walking the schema as the decoder walks the bytes.
class Namer {
 public:
  Namer(const Schema& schema, const Limits& limits, const DecodedMessage& m, std::vector<std::string>& names)
      : schema_(schema), limits_(limits), m_(m), names_(names) {}

  void message(std::size_t index, const std::string& prefix) {
    const MessageType& type = schema_.types[index];
    const std::string* labels = nullptr;
    std::size_t label_count = 0;
    for (std::size_t k = 0; k < type.fields.size(); ++k) {
      const Field& f = type.fields[k];
      const std::string name = prefix + f.name;
      if (!f.is_array) {
        if (f.type == Primitive::message) {
          message(f.nested, name + ".");
        } else if (f.type != Primitive::string) {
          names_.push_back(name);
        }
        continue;
      }
      std::size_t n = f.fixed_length;
      if (n == 0) n = next_length < m_.lengths.size() ? m_.lengths[next_length++] : 0;
      if (n > limits_.max_array) continue;
      if (static_cast<int>(k) == type.label_field) {
        if (next_label + n <= m_.labels.size()) {
          labels = m_.labels.data() + next_label;
          label_count = n;
          next_label += n;
        }
        continue;
      }
      if (f.type == Primitive::string) continue;
      const bool frames = f.type == Primitive::message && schema_.types[f.nested].frame_field >= 0;
      for (std::size_t i = 0; i < n; ++i) {
        std::string element =
            name + "." + (labels != nullptr && label_count == n && !labels[i].empty() ? labels[i] : std::to_string(i));
        if (frames) {  // each element's child_frame_id, as the walk met it
          const std::string* frame = next_label < m_.labels.size() ? &m_.labels[next_label++] : nullptr;
          element = name + "." + (frame != nullptr && !frame->empty() ? *frame : std::to_string(i));
        }
        if (f.type == Primitive::message) {
          message(f.nested, element + ".");
        } else {
          names_.push_back(element);
        }
      }
    }
    if (type.is_quaternion) {
      for (const char* angle : {"roll", "pitch", "yaw"}) names_.push_back(prefix + angle);
    }
  }

  std::size_t next_length = 0;
  std::size_t next_label = 0;

 private:
  const Schema& schema_;
  const Limits& limits_;
  const DecodedMessage& m_;
  std::vector<std::string>& names_;
};

}  // namespace

Decoder::Decoder(Schema schema, Encoding encoding, Limits limits)
    : schema_(std::move(schema)), encoding_(encoding), limits_(limits) {
  // A nested type always comes after the types that use it.
  min_size_.assign(schema_.types.size(), 0);
  for (std::size_t i = schema_.types.size(); i-- > 0;) {
    std::size_t total = 0;
    for (const Field& f : schema_.types[i].fields) {
      const std::size_t element = f.type == Primitive::message ? min_size_[f.nested] : primitive_size(f.type);
      const std::size_t bytes = !f.is_array           ? element
                                : f.fixed_length == 0 ? 4
                                                      : saturated_product(f.fixed_length, element);
      total = std::min(kHuge, total + bytes);
    }
    min_size_[i] = total;
  }
  const MessageType& root = schema_.types[0];
  if (!root.fields.empty() && root.fields[0].type == Primitive::message && !root.fields[0].is_array &&
      schema_.types[root.fields[0].nested].name == "std_msgs/Header") {
    const MessageType& header = schema_.types[root.fields[0].nested];
    for (std::size_t k = 0; k < header.fields.size(); ++k) {
      if (header.fields[k].name == "stamp" && header.fields[k].type == Primitive::time && !header.fields[k].is_array) {
        header_stamp_field_ = static_cast<int>(k);
      }
    }
  }
}

void Decoder::decode(const std::uint8_t* data, std::size_t size, DecodedMessage& out) const {
  out.values.clear();
  out.lengths.clear();
  out.label_count = 0;
  out.labels_changed = false;
  out.header_stamp_ns = -1;
  Walk(*this, data, size, out).run();
  if (out.labels.size() != out.label_count) {  // fewer labels than the previous message
    out.labels.resize(out.label_count);
    out.labels_changed = true;
  }
}

std::vector<std::string> Decoder::value_names(const DecodedMessage& message) const {
  std::vector<std::string> names;
  names.reserve(message.values.size());
  Namer(schema_, limits_, message, names).message(0, "");
  return names;
}

}  // namespace roverlab::io::ros
