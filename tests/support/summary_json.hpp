#pragma once
// The one-object JSON summary a program writes (fsw_app --summary-json),
// read back with typed look-ups: a missing or mistyped key reads as "",
// -1 or false, so a check against it fails rather than crashes.
#include <initializer_list>
#include <string>

#include "formats/json.hpp"
#include "test_data.hpp"

namespace testing_support {

struct Summary {
  formats::JsonValue json;
  std::string text(const char* key) const {
    const formats::JsonValue* v = json.find(key);
    return v && v->is_string() ? v->text : "";
  }
  double number(const char* key) const {
    const formats::JsonValue* v = json.find(key);
    return v && v->is_number() ? v->number : -1.0;
  }
  bool flag(const char* key) const {
    const formats::JsonValue* v = json.find(key);
    return v && v->is_bool() && v->boolean;
  }
  // Inside nested objects: {"camera", "usb", "state"}; nullptr when any
  // key on the way is missing.
  const formats::JsonValue* at(std::initializer_list<const char*> path) const {
    const formats::JsonValue* v = &json;
    for (const char* key : path) v = v ? v->find(key) : nullptr;
    return v;
  }
  double number_at(std::initializer_list<const char*> path) const {
    const formats::JsonValue* v = at(path);
    return v && v->is_number() ? v->number : -1.0;
  }
  std::string text_at(std::initializer_list<const char*> path) const {
    const formats::JsonValue* v = at(path);
    return v && v->is_string() ? v->text : "";
  }
};

// Reads and parses `path`; false with the parser's message in `error`.
inline bool read_summary(const std::string& path, Summary* out, std::string* error) {
  return formats::parse_json(read_text(path), &out->json, error);
}

}  // namespace testing_support
