#include "importers/ros_msg_definition.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <optional>
#include <set>
#include <string_view>

namespace roverlab::io::ros {

namespace {

// A definition deeper than this is refused (a real one is a few levels deep).
constexpr std::size_t kMaxDepth = 64;
// A fixed-length array longer than this is refused (its bytes would be
// claimed before any message is read).
constexpr std::size_t kMaxFixedLength = std::size_t{1} << 24;

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

// "pkg/msg/Type" -> "pkg/Type".
std::string canonical_name(std::string_view name) {
  std::string out(trim(name));
  const std::size_t msg = out.find("/msg/");
  if (msg != std::string::npos) out.erase(msg, 4);
  return out;
}

std::string package_of(const std::string& type) {
  const std::size_t slash = type.find('/');
  return slash == std::string::npos ? std::string() : type.substr(0, slash);
}

struct RawField {
  std::string type;  // base type as written, array suffix removed
  std::string name;
  bool is_array = false;
  std::size_t fixed_length = 0;
  std::size_t line = 0;
};

struct Section {
  std::string name;
  std::vector<RawField> fields;
};

std::optional<Primitive> builtin(const std::string& type, Dialect dialect) {
  static const std::map<std::string, Primitive> common = {
      {"bool", Primitive::boolean},    {"int8", Primitive::int8},       {"uint8", Primitive::uint8},
      {"int16", Primitive::int16},     {"uint16", Primitive::uint16},   {"int32", Primitive::int32},
      {"uint32", Primitive::uint32},   {"int64", Primitive::int64},     {"uint64", Primitive::uint64},
      {"float32", Primitive::float32}, {"float64", Primitive::float64}, {"string", Primitive::string},
      {"char", Primitive::uint8},
  };
  const auto it = common.find(type);
  if (it != common.end()) return it->second;
  if (dialect == Dialect::ros1) {
    if (type == "byte") return Primitive::int8;  // ROS 1: a deprecated alias of int8
    if (type == "time") return Primitive::time;
    if (type == "duration") return Primitive::duration;
  } else {
    if (type == "byte") return Primitive::uint8;  // ROS 2: an octet
    if (type == "builtin_interfaces/Time") return Primitive::time;
    if (type == "builtin_interfaces/Duration") return Primitive::duration;
  }
  return std::nullopt;
}

// Parses one field line; nullopt for a blank line, a comment or a constant.
std::optional<RawField> parse_line(std::string_view line, std::size_t number, const std::string& section) {
  const std::string where = "line " + std::to_string(number) + " (" + section + ")";
  // A constant ("int32 X=1", "string S=a # b") has '=' before any comment.
  const std::size_t hash = line.find('#');
  const std::size_t eq = line.find('=');
  if (eq != std::string_view::npos && (hash == std::string_view::npos || eq < hash)) {
    // ROS 2 bounded types ("string<=8 s", "int32[<=4] a") are not constants.
    const std::string_view before = line.substr(0, eq);
    if (before.empty() || before.back() != '<') return std::nullopt;
  }
  if (hash != std::string_view::npos) line = line.substr(0, hash);
  line = trim(line);
  if (line.empty()) return std::nullopt;
  std::size_t space = 0;
  while (space < line.size() && !std::isspace(static_cast<unsigned char>(line[space]))) ++space;
  std::string_view type = line.substr(0, space);
  std::string_view rest = trim(line.substr(space));
  std::size_t name_end = 0;
  while (name_end < rest.size() && !std::isspace(static_cast<unsigned char>(rest[name_end]))) ++name_end;
  const std::string_view name = rest.substr(0, name_end);  // a ROS 2 default value may follow
  if (type.empty() || name.empty()) throw DefinitionError(where + ": expected 'TYPE NAME'");
  RawField f;
  f.name = std::string(name);
  f.line = number;
  const std::size_t open = type.find('[');
  if (open != std::string_view::npos) {
    const std::size_t close = type.find(']', open);
    if (close == std::string_view::npos || close + 1 != type.size()) {
      throw DefinitionError(where + ": malformed array type '" + std::string(type) + "'");
    }
    f.is_array = true;
    std::string_view length = type.substr(open + 1, close - open - 1);
    if (length.substr(0, 2) == "<=") {
      length = {};  // ROS 2 bounded sequence: variable length on the wire
    }
    if (!length.empty()) {
      std::size_t n = 0;
      for (char c : length) {
        if (!std::isdigit(static_cast<unsigned char>(c)) || n > kMaxFixedLength) {
          throw DefinitionError(where + ": bad array length '" + std::string(length) + "'");
        }
        n = n * 10 + static_cast<std::size_t>(c - '0');
      }
      if (n == 0 || n > kMaxFixedLength) {
        throw DefinitionError(where + ": array length " + std::string(length) + " out of range");
      }
      f.fixed_length = n;
    }
    type = type.substr(0, open);
  }
  const std::size_t bound = type.find("<=");
  if (bound != std::string_view::npos) type = type.substr(0, bound);  // ROS 2 bounded string
  f.type = std::string(type);
  return f;
}

std::vector<Section> split_sections(const std::string& root_type, const std::string& text) {
  std::vector<Section> sections(1);
  sections[0].name = canonical_name(root_type);
  bool expect_msg_line = false;
  std::size_t number = 0;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    const std::string_view line = trim(std::string_view(text).substr(begin, end - begin));
    begin = end + 1;
    ++number;
    if (line.size() >= 3 && line.find_first_not_of('=') == std::string_view::npos) {
      sections.emplace_back();
      expect_msg_line = true;
      continue;
    }
    if (expect_msg_line) {
      if (line.empty() || line.front() == '#') continue;
      if (line.substr(0, 4) != "MSG:") {
        throw DefinitionError("line " + std::to_string(number) + ": expected 'MSG: pkg/Type' after a line of '='");
      }
      sections.back().name = canonical_name(line.substr(4));
      if (sections.back().name.empty()) throw DefinitionError("line " + std::to_string(number) + ": empty MSG name");
      expect_msg_line = false;
      continue;
    }
    if (auto f = parse_line(line, number, sections.back().name)) sections.back().fields.push_back(std::move(*f));
  }
  if (expect_msg_line) throw DefinitionError("the definition ends after a line of '=' without 'MSG: pkg/Type'");
  return sections;
}

class Builder {
 public:
  Builder(const std::vector<Section>& sections, Dialect dialect) : dialect_(dialect) {
    for (const auto& s : sections) by_name_.emplace(s.name, &s);  // the first definition of a name counts
    schema_.dialect = dialect;
  }

  Schema build(const Section& root) {
    add(root, 0);
    return std::move(schema_);
  }

 private:
  std::string resolve(const std::string& type, const std::string& within) const {
    if (dialect_ == Dialect::ros1 && type == "Header") return "std_msgs/Header";
    if (type.find('/') != std::string::npos) return canonical_name(type);
    const std::string package = package_of(within);
    return package.empty() ? type : package + "/" + type;
  }

  const Section& find(const std::string& name, const std::string& from) const {
    auto it = by_name_.find(name);
    if (it == by_name_.end()) {
      // A definition may name a nested type by its bare name.
      const std::size_t slash = name.rfind('/');
      if (slash != std::string::npos) {
        std::vector<const Section*> matches;
        for (const auto& [full, section] : by_name_) {
          if (full.size() > name.size() - slash &&
              full.compare(full.size() - (name.size() - slash), name.size() - slash, name, slash) == 0) {
            matches.push_back(section);
          }
        }
        if (matches.size() == 1) return *matches.front();
      }
      throw DefinitionError("type " + from + " refers to unknown type " + name);
    }
    return *it->second;
  }

  std::size_t add(const Section& section, std::size_t depth) {
    if (depth > kMaxDepth) throw DefinitionError("types nested deeper than " + std::to_string(kMaxDepth));
    if (std::find(stack_.begin(), stack_.end(), section.name) != stack_.end()) {
      throw DefinitionError("type " + section.name + " contains itself");
    }
    const auto done = index_.find(section.name);
    if (done != index_.end()) return done->second;
    stack_.push_back(section.name);
    const std::size_t index = schema_.types.size();
    schema_.types.emplace_back();
    schema_.types[index].name = section.name;
    std::vector<Field> fields;
    for (const RawField& raw : section.fields) {
      Field f;
      f.name = raw.name;
      f.is_array = raw.is_array;
      f.fixed_length = raw.fixed_length;
      const std::string resolved = resolve(raw.type, section.name);
      if (auto p = builtin(raw.type, dialect_)) {
        f.type = *p;
      } else if (auto q = builtin(resolved, dialect_)) {
        f.type = *q;
      } else if (raw.type == "wstring") {
        throw DefinitionError("type " + section.name + ": wstring fields are not supported");
      } else {
        f.type = Primitive::message;
        f.nested = add(find(resolved, section.name), depth + 1);
      }
      fields.push_back(std::move(f));
    }
    MessageType& t = schema_.types[index];  // add() may have grown the vector
    t.fields = std::move(fields);
    t.is_quaternion = t.fields.size() == 4 && std::all_of(t.fields.begin(), t.fields.end(), [](const Field& f) {
                        return f.type == Primitive::float64 && !f.is_array;
                      });
    if (t.is_quaternion) {
      const char* names[] = {"x", "y", "z", "w"};
      for (std::size_t k = 0; k < 4; ++k) t.is_quaternion = t.is_quaternion && t.fields[k].name == names[k];
    }
    for (std::size_t k = 0; k < t.fields.size(); ++k) {
      const Field& f = t.fields[k];
      if (f.name == "name" && f.type == Primitive::string && f.is_array && f.fixed_length == 0) {
        t.label_field = static_cast<int>(k);
        break;
      }
    }
    bool nested_labels = false;
    for (const Field& f : t.fields) {
      nested_labels = nested_labels || (f.type == Primitive::message && schema_.types[f.nested].has_labels);
    }
    for (std::size_t k = 0; k < t.fields.size() && t.label_field < 0 && !nested_labels; ++k) {
      const Field& f = t.fields[k];
      if (f.name == "child_frame_id" && f.type == Primitive::string && !f.is_array) t.frame_field = static_cast<int>(k);
    }
    t.has_labels = nested_labels || t.label_field >= 0 || t.frame_field >= 0;
    index_.emplace(section.name, index);
    stack_.pop_back();
    return index;
  }

  Dialect dialect_;
  std::map<std::string, const Section*> by_name_;
  std::map<std::string, std::size_t> index_;
  std::vector<std::string> stack_;
  Schema schema_;
};

}  // namespace

Schema parse_definition(const std::string& root_type, const std::string& text, Dialect dialect) {
  const std::vector<Section> sections = split_sections(root_type, text);
  if (sections[0].name.empty()) throw DefinitionError("the message type has no name");
  return Builder(sections, dialect).build(sections[0]);
}

}  // namespace roverlab::io::ros
