#pragma once
// JSON for configuration, scenario and summary files, parsed by
// nlohmann-json's SAX reader into a small tree in which every value
// remembers its line, so that errors can say where the problem is. Bounded
// on hostile input: duplicate keys found in constant time each, nesting
// limited to kMaxJsonDepth, values to kMaxJsonValues, whole files to
// kMaxTextFileBytes by the reader
// (text_file.hpp). Not for flight paths: it allocates freely.
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace formats {

constexpr int kMaxJsonDepth = 64;
// Every value costs about 150 bytes in the tree: a million of them is
// 150 MB, already more than a configuration could want on a 512 MB board.
constexpr std::size_t kMaxJsonValues = std::size_t{1} << 20;

class JsonValue {
 public:
  enum class Type { kNull, kBool, kNumber, kString, kArray, kObject };

  Type type = Type::kNull;
  int line = 0;
  bool boolean = false;
  double number = 0.0;
  std::string text;
  std::vector<JsonValue> items;                            // arrays
  std::vector<std::pair<std::string, JsonValue>> members;  // objects, in file order

  bool is_object() const { return type == Type::kObject; }
  bool is_array() const { return type == Type::kArray; }
  bool is_number() const { return type == Type::kNumber; }
  bool is_string() const { return type == Type::kString; }
  bool is_bool() const { return type == Type::kBool; }
  // nullptr when absent or when this is not an object.
  const JsonValue* find(std::string_view key) const;
};

const char* to_string(JsonValue::Type type);

// Parses a whole document. On failure returns false and sets *error to
// "line N: what was wrong".
bool parse_json(std::string_view text, JsonValue* out, std::string* error);

// Reads (bounded, regular files only) and parses a file. On failure *error
// is "PATH:N: what was wrong" (N the line) or "PATH: why it cannot be read".
bool load_json_file(const std::string& path, JsonValue* out, std::string* error);

}  // namespace formats
