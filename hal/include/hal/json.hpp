#pragma once
// A small JSON reader for configuration and scenario files. Every value
// remembers its line so that errors can say where the problem is. Not for
// flight paths: it allocates freely.
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hal {

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

}  // namespace hal
