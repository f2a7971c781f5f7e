#pragma once
// JSON resources (rovers, soils, scenarios, mappings): reading the file and
// typed, checked access to its fields. Every error is an InputError naming the
// file and the field, e.g. "rovers/x.json: field 'links[2].theta': expected a
// number, got a string".

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace roverlab::io {

// JSON from data files (resources, stored results, campaign metrics, layouts)
// nests at most this deep: a value nested 100,000 deep overflows the stack of
// any recursive copy, comparison or destruction of it.
constexpr std::size_t kMaxJsonNesting = 64;

// The deepest nesting of arrays and objects in JSON text (brackets inside
// strings do not count), found without parsing.
std::size_t json_nesting(std::string_view text);

// `text` parsed when it is valid JSON nested at most `max_nesting` deep; a
// discarded value (is_discarded()) otherwise. Never throws.
nlohmann::json parse_bounded_json(std::string_view text, std::size_t max_nesting = kMaxJsonNesting);

// A value inside a resource file with its place in it: "" for the top level,
// "links[2].theta" deeper down. Refers to the document of a JsonResource,
// which must outlive it.
class JsonNode {
 public:
  JsonNode(std::string file, const nlohmann::json& value, std::string where = "");

  const std::string& file() const { return file_; }
  const nlohmann::json& value() const { return *value_; }
  const std::string& where() const { return where_; }

  // True when this node is an object holding `field`.
  bool has(const std::string& field) const;
  // The place of `field` inside this node ("links[2]" + "theta").
  std::string place_of(const std::string& field) const;
  // The node of a field this object holds (check with has() first).
  JsonNode child(const std::string& field) const;

  // InputError(file, "field 'WHERE': PROBLEM"), or "PROBLEM" at the top level.
  [[noreturn]] void fail(const std::string& problem) const;
  // InputError(file, "field 'WHERE.FIELD': PROBLEM").
  [[noreturn]] void fail(const std::string& field, const std::string& problem) const;

 private:
  std::string file_;
  const nlohmann::json* value_;
  std::string where_;
};

// A parsed resource file.
class JsonResource {
 public:
  JsonResource(std::string file, nlohmann::json document) : file_(std::move(file)), document_(std::move(document)) {}
  JsonResource(const JsonResource&) = delete;
  JsonResource& operator=(const JsonResource&) = delete;
  const std::string& file() const { return file_; }
  JsonNode root() const { return {file_, document_}; }

 private:
  std::string file_;
  nlohmann::json document_;
};

// Reads `path` as a JSON object. `what` names the resource in the messages
// ("cannot open soil file", "soil file is not valid JSON: ...").
JsonResource read_json_resource(const std::string& path, const std::string& what);

// Checks the "format" field: "not a RoverLab soil ('format' must be
// \"roverlab-soil\")" otherwise.
void require_format(const JsonNode& root, const std::string& format, const std::string& what);

// The value of a node, checked: a finite number, a string.
double as_number(const JsonNode& node);
std::string as_string(const JsonNode& node);

// Fields of an object node. required_*: missing is an error; optional_*:
// missing gives the fallback, a present field of the wrong type is an error.
JsonNode required_field(const JsonNode& node, const std::string& field, const char* expected);
double required_number(const JsonNode& node, const std::string& field);
double optional_number(const JsonNode& node, const std::string& field, double fallback);
// A number in [lo, hi].
double required_number_in(const JsonNode& node, const std::string& field, double lo, double hi);
std::string required_string(const JsonNode& node, const std::string& field);
std::string optional_string(const JsonNode& node, const std::string& field, const std::string& fallback);
JsonNode required_object(const JsonNode& node, const std::string& field);
// The elements of an array field, each with its place ("links[2]").
std::vector<JsonNode> required_array(const JsonNode& node, const std::string& field);
// An array of exactly `count` numbers.
std::vector<double> required_numbers(const JsonNode& node, const std::string& field, std::size_t count);

}  // namespace roverlab::io
