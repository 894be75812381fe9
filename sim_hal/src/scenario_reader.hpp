#pragma once
// The scenario reader's shared parts (private to sim_hal/src): the Reader
// that collects the first error with its line, and the rack-wall element's
// reader, which lives in its own file (scenario_rack_wall.cpp).
#include <initializer_list>
#include <sstream>
#include <string>

#include "formats/json.hpp"
#include "sim_hal/scene.hpp"

namespace sim_hal {
namespace scenario_detail {

using formats::JsonValue;

// Collects the first error with its line; later checks become no-ops.
class Reader {
 public:
  explicit Reader(std::string path) : path_(std::move(path)) {}
  bool ok() const { return error_.empty(); }
  const std::string& path() const { return path_; }
  const std::string& error() const { return error_; }

  bool fail(const JsonValue& at, const std::string& what) {
    if (ok()) error_ = path_ + ":" + std::to_string(at.line) + ": " + what;
    return false;
  }

  const JsonValue* member(const JsonValue& obj, const char* key, JsonValue::Type type,
                          bool required) {
    const JsonValue* v = obj.find(key);
    if (!v) {
      if (required) fail(obj, std::string("missing \"") + key + "\"");
      return nullptr;
    }
    if (v->type != type) {
      fail(*v, std::string("\"") + key + "\" must be a " + formats::to_string(type) + ", not a " +
                   formats::to_string(v->type));
      return nullptr;
    }
    return v;
  }

  bool number(const JsonValue& obj, const char* key, double lo, double hi, double* out,
              bool required) {
    const JsonValue* v = member(obj, key, JsonValue::Type::kNumber, required);
    if (!v) return !required && ok();
    if (!(v->number >= lo && v->number <= hi)) {
      std::ostringstream m;
      m << "\"" << key << "\" = " << v->number << " is outside " << lo << " .. " << hi;
      return fail(*v, m.str());
    }
    *out = v->number;
    return true;
  }

  bool vec3(const JsonValue& obj, const char* key, Eigen::Vector3d* out, bool required,
            bool unit = false) {
    const JsonValue* v = member(obj, key, JsonValue::Type::kArray, required);
    if (!v) return !required && ok();
    if (v->items.size() != 3) return fail(*v, std::string("\"") + key + "\" must have 3 numbers");
    for (int k = 0; k < 3; ++k) {
      if (!v->items[k].is_number())
        return fail(v->items[k], std::string("\"") + key + "\" must hold numbers");
      (*out)[k] = v->items[k].number;
    }
    if (unit) {
      if (out->norm() < 1e-9) return fail(*v, std::string("\"") + key + "\" must not be zero");
      out->normalize();
    }
    return true;
  }

  // [a, b] with a < b, both within lo .. hi.
  bool range(const JsonValue& obj, const char* key, double lo, double hi, double* a, double* b,
             bool required) {
    const JsonValue* v = member(obj, key, JsonValue::Type::kArray, required);
    if (!v) return !required && ok();
    if (v->items.size() != 2 || !v->items[0].is_number() || !v->items[1].is_number()) {
      return fail(*v, std::string("\"") + key + "\" must be [from_m, to_m]");
    }
    const double x = v->items[0].number, y = v->items[1].number;
    if (!(x >= lo && y <= hi && x < y)) {
      std::ostringstream m;
      m << "\"" << key << "\" = [" << x << ", " << y << "] must rise within " << lo << " .. " << hi;
      return fail(*v, m.str());
    }
    *a = x;
    *b = y;
    return true;
  }

  bool vec2(const JsonValue& obj, const char* key, double lo, double hi, Eigen::Vector2d* out,
            bool required) {
    const JsonValue* v = member(obj, key, JsonValue::Type::kArray, required);
    if (!v) return !required && ok();
    if (v->items.size() != 2 || !v->items[0].is_number() || !v->items[1].is_number()) {
      return fail(*v, std::string("\"") + key + "\" must be [u_m, v_m]");
    }
    for (int k = 0; k < 2; ++k) {
      if (!(v->items[k].number >= lo && v->items[k].number <= hi)) {
        std::ostringstream m;
        m << "\"" << key << "\" holds " << v->items[k].number << ", outside " << lo << " .. " << hi;
        return fail(v->items[k], m.str());
      }
      (*out)[k] = v->items[k].number;
    }
    return true;
  }

  bool flag(const JsonValue& obj, const char* key, bool* out) {
    const JsonValue* v = member(obj, key, JsonValue::Type::kBool, false);
    if (v) *out = v->boolean;
    return ok();
  }

  void unknown_keys(const JsonValue& obj, std::initializer_list<const char*> known,
                    const char* where) {
    for (const auto& m : obj.members) {
      bool found = false;
      for (const char* k : known) found = found || m.first == k;
      if (!found) fail(m.second, "unknown key \"" + m.first + "\" in " + where);
    }
  }

 private:
  std::string path_;
  std::string error_;
};

// A "rack_walls" entry: faces, seat tracks, gaps, bays, strips and lights
// added to the scene.
void read_rack_wall(Reader& r, const JsonValue& rw, Scene* scene);

}  // namespace scenario_detail
}  // namespace sim_hal
