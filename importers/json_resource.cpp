#include "importers/json_resource.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>

#include "core/common/error.h"

namespace roverlab::io {

using nlohmann::json;

namespace {

std::string type_of(const json& value) {
  switch (value.type()) {
    case json::value_t::null:
      return "null";
    case json::value_t::object:
      return "an object";
    case json::value_t::array:
      return "an array";
    case json::value_t::string:
      return "a string";
    case json::value_t::boolean:
      return "a boolean";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
    case json::value_t::number_float:
      return "a number";
    default:
      return "an unsupported value";
  }
}

std::string short_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

std::size_t json_nesting(std::string_view text) {
  std::size_t depth = 0;
  std::size_t deepest = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') {
        ++i;  // the escaped character
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return deepest;
}

json parse_bounded_json(std::string_view text, std::size_t max_nesting) {
  if (json_nesting(text) > max_nesting) return json(json::value_t::discarded);
  return json::parse(text.begin(), text.end(), nullptr, false);
}

JsonNode::JsonNode(std::string file, const json& value, std::string where)
    : file_(std::move(file)), value_(&value), where_(std::move(where)) {}

bool JsonNode::has(const std::string& field) const { return value_->is_object() && value_->contains(field); }

std::string JsonNode::place_of(const std::string& field) const { return where_.empty() ? field : where_ + "." + field; }

JsonNode JsonNode::child(const std::string& field) const { return {file_, value_->at(field), place_of(field)}; }

void JsonNode::fail(const std::string& problem) const {
  throw InputError(file_, where_.empty() ? problem : "field '" + where_ + "': " + problem);
}

void JsonNode::fail(const std::string& field, const std::string& problem) const {
  throw InputError(file_, "field '" + place_of(field) + "': " + problem);
}

JsonResource read_json_resource(const std::string& path, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open " + what);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (json_nesting(text) > kMaxJsonNesting) {
    throw InputError(path, what + " nests deeper than " + std::to_string(kMaxJsonNesting) + " levels");
  }
  json document;
  try {
    document = json::parse(text);
  } catch (const json::exception& e) {
    // parse_error, and out_of_range for a number beyond a double ("1E400",
    // found by fuzzing: it escaped as an internal failure).
    throw InputError(path, what + " is not valid JSON: " + e.what());
  }
  if (!document.is_object()) {
    throw InputError(path, what + ": expected a JSON object at the top level, got " + type_of(document));
  }
  return {path, std::move(document)};
}

void require_format(const JsonNode& root, const std::string& format, const std::string& what) {
  if (!root.has("format") || root.value().at("format") != format) {
    root.fail("not a RoverLab " + what + " ('format' must be \"" + format + "\")");
  }
}

double as_number(const JsonNode& node) {
  if (!node.value().is_number()) node.fail("expected a number, got " + type_of(node.value()));
  const double v = node.value().get<double>();
  if (!std::isfinite(v)) node.fail("expected a finite number");
  return v;
}

std::string as_string(const JsonNode& node) {
  if (!node.value().is_string()) node.fail("expected a string, got " + type_of(node.value()));
  return node.value().get<std::string>();
}

JsonNode required_field(const JsonNode& node, const std::string& field, const char* expected) {
  if (!node.value().is_object()) node.fail("expected an object, got " + type_of(node.value()));
  if (!node.has(field)) node.fail(field, std::string("missing, expected ") + expected);
  return node.child(field);
}

double required_number(const JsonNode& node, const std::string& field) {
  return as_number(required_field(node, field, "a number"));
}

double optional_number(const JsonNode& node, const std::string& field, double fallback) {
  return node.has(field) ? as_number(node.child(field)) : fallback;
}

double required_number_in(const JsonNode& node, const std::string& field, double lo, double hi) {
  const double v = required_number(node, field);
  if (v < lo || v > hi) {
    node.fail(field, short_number(v) + " is outside [" + short_number(lo) + ", " + short_number(hi) + "]");
  }
  return v;
}

std::string required_string(const JsonNode& node, const std::string& field) {
  return as_string(required_field(node, field, "a string"));
}

std::string optional_string(const JsonNode& node, const std::string& field, const std::string& fallback) {
  return node.has(field) ? as_string(node.child(field)) : fallback;
}

JsonNode required_object(const JsonNode& node, const std::string& field) {
  JsonNode object = required_field(node, field, "an object");
  if (!object.value().is_object()) object.fail("expected an object, got " + type_of(object.value()));
  return object;
}

std::vector<JsonNode> required_array(const JsonNode& node, const std::string& field) {
  const JsonNode array = required_field(node, field, "an array");
  if (!array.value().is_array()) array.fail("expected an array, got " + type_of(array.value()));
  std::vector<JsonNode> elements;
  for (std::size_t k = 0; k < array.value().size(); ++k) {
    elements.emplace_back(node.file(), array.value()[k], array.where() + "[" + std::to_string(k) + "]");
  }
  return elements;
}

std::vector<double> required_numbers(const JsonNode& node, const std::string& field, std::size_t count) {
  const std::vector<JsonNode> elements = required_array(node, field);
  if (elements.size() != count) {
    node.fail(field, "expected " + std::to_string(count) + " numbers, got " + std::to_string(elements.size()));
  }
  std::vector<double> out;
  out.reserve(elements.size());
  for (const auto& e : elements) out.push_back(as_number(e));
  return out;
}

}  // namespace roverlab::io
