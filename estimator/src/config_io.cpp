#include "estimator/config_io.hpp"

#include <cmath>
#include <cstdio>

#include "formats/json.hpp"
#include "formats/text_file.hpp"

namespace estimator {
namespace {

using formats::JsonValue;

struct FloatKey {
  const char* name;
  float estimator::DetectorConfig::*field;
};
struct UintKey {
  const char* name;
  std::uint32_t estimator::DetectorConfig::*field;
};

constexpr FloatKey kFloatKeys[] = {
    {"min_range_m", &estimator::DetectorConfig::min_range_m},
    {"max_range_m", &estimator::DetectorConfig::max_range_m},
    {"max_find_range_m", &estimator::DetectorConfig::max_find_range_m},
    {"plane_inlier_m", &estimator::DetectorConfig::plane_inlier_m},
    {"plane_min_inlier_fraction", &estimator::DetectorConfig::plane_min_inlier_fraction},
    {"gap_margin_m", &estimator::DetectorConfig::gap_margin_m},
    {"cross_delta_m", &estimator::DetectorConfig::cross_delta_m},
    {"wall_tolerance_m", &estimator::DetectorConfig::wall_tolerance_m},
    {"side_width_min_ratio", &estimator::DetectorConfig::side_width_min_ratio},
    {"side_width_max_ratio", &estimator::DetectorConfig::side_width_max_ratio},
    {"run_peak_tolerance_m", &estimator::DetectorConfig::run_peak_tolerance_m},
    {"line_inlier_m", &estimator::DetectorConfig::line_inlier_m},
    {"cluster_gap_m", &estimator::DetectorConfig::cluster_gap_m},
    {"line_max_turn_deg", &estimator::DetectorConfig::line_max_turn_deg},
    {"beam_length_min_ratio", &estimator::DetectorConfig::beam_length_min_ratio},
    {"beam_length_max_ratio", &estimator::DetectorConfig::beam_length_max_ratio},
    {"min_visible_length_m", &estimator::DetectorConfig::min_visible_length_m},
    {"min_visible_fraction", &estimator::DetectorConfig::min_visible_fraction},
    {"front_height_tolerance_m", &estimator::DetectorConfig::front_height_tolerance_m},
    {"own_surface_min_tilt_deg", &estimator::DetectorConfig::own_surface_min_tilt_deg},
    {"profile_min_obliquity_deg", &estimator::DetectorConfig::profile_min_obliquity_deg},
    {"profile_min_spread_m", &estimator::DetectorConfig::profile_min_spread_m},
    {"clearance_low_m", &estimator::DetectorConfig::clearance_low_m},
    {"clearance_high_m", &estimator::DetectorConfig::clearance_high_m},
    {"clearance_max_solid_fraction", &estimator::DetectorConfig::clearance_max_solid_fraction},
    {"end_search_m", &estimator::DetectorConfig::end_search_m},
    {"end_drop_max_m", &estimator::DetectorConfig::end_drop_max_m},
    {"target_standoff_m", &estimator::DetectorConfig::target_standoff_m},
    {"mount_search_m", &estimator::DetectorConfig::mount_search_m},
    {"mount_bay_min_m", &estimator::DetectorConfig::mount_bay_min_m},
    {"mount_bay_max_m", &estimator::DetectorConfig::mount_bay_max_m},
    {"mount_step_m", &estimator::DetectorConfig::mount_step_m},
    {"mount_min_fraction", &estimator::DetectorConfig::mount_min_fraction},
    {"mount_beside_min_m", &estimator::DetectorConfig::mount_beside_min_m},
    {"mount_beside_max_m", &estimator::DetectorConfig::mount_beside_max_m},
    {"mount_beside_tolerance_m", &estimator::DetectorConfig::mount_beside_tolerance_m},
    {"mount_beside_min_fraction", &estimator::DetectorConfig::mount_beside_min_fraction},
};
constexpr UintKey kUintKeys[] = {
    {"plane_iterations", &estimator::DetectorConfig::plane_iterations},
    {"plane_max_iterations", &estimator::DetectorConfig::plane_max_iterations},
    {"plane_score_samples", &estimator::DetectorConfig::plane_score_samples},
    {"line_iterations", &estimator::DetectorConfig::line_iterations},
    {"line_score_samples", &estimator::DetectorConfig::line_score_samples},
    {"min_line_inliers", &estimator::DetectorConfig::min_line_inliers},
    {"line_attempts", &estimator::DetectorConfig::line_attempts},
    {"max_width", &estimator::DetectorConfig::max_width},
    {"max_height", &estimator::DetectorConfig::max_height},
    {"max_mount_hypotheses", &estimator::DetectorConfig::max_mount_hypotheses},
    {"max_mount_hypotheses_bay", &estimator::DetectorConfig::max_mount_hypotheses_bay},
    {"front_peak_mounts", &estimator::DetectorConfig::front_peak_mounts},
    {"mount_accept_inliers", &estimator::DetectorConfig::mount_accept_inliers},
    {"mount_beside_min_pixels", &estimator::DetectorConfig::mount_beside_min_pixels},
    {"track_beside_min_pixels", &estimator::DetectorConfig::track_beside_min_pixels},
};

std::string at(const std::string& path, const JsonValue& v) {
  return path + ":" + std::to_string(v.line) + ": ";
}

// "handrail_types": the names of the known lengths to accept, a subset of
// the built-in list (the names are the detector's own strings); [] leaves
// only handrail.bar_length_m.
bool read_handrail_types(const JsonValue& v, const std::string& path, const std::string& quoted_key,
                         estimator::DetectorConfig* c, std::string* error) {
  const estimator::DetectorConfig defaults;
  std::string known;
  for (std::uint32_t k = 0; k < defaults.handrail_type_count; ++k) {
    known += std::string(k ? ", " : "") + "\"" + defaults.handrail_types[k].name + "\"";
  }
  if (!v.is_array()) {
    *error = at(path, v) + quoted_key + " must be an array of type names (" + known + ")";
    return false;
  }
  c->handrail_type_count = 0;
  for (const JsonValue& item : v.items) {
    const estimator::HandrailType* type = nullptr;
    for (std::uint32_t k = 0; item.is_string() && k < defaults.handrail_type_count; ++k) {
      if (item.text == defaults.handrail_types[k].name) type = &defaults.handrail_types[k];
    }
    if (type == nullptr) {
      *error = at(path, item) + quoted_key + ": unknown handrail type " +
               (item.is_string() ? "\"" + item.text + "\"" : std::string("(not a string)")) +
               "; known: " + known;
      return false;
    }
    for (std::uint32_t k = 0; k < c->handrail_type_count; ++k) {
      if (c->handrail_types[k].name == type->name) {
        *error = at(path, item) + quoted_key + ": \"" + item.text + "\" is listed twice";
        return false;
      }
    }
    c->handrail_types[c->handrail_type_count++] = *type;
  }
  return true;
}

bool read_handrail(const JsonValue& h, const std::string& path, estimator::HandrailGeometry* g,
                   std::string* error) {
  if (!h.is_object()) {
    *error = at(path, h) + "\"handrail\" must be an object";
    return false;
  }
  double length = g->bar_length_m;
  if (const JsonValue* l = h.find("bar_length_m")) {
    if (!l->is_number()) {
      *error = at(path, *l) + "\"handrail.bar_length_m\" must be a number";
      return false;
    }
    length = l->number;
  }
  if (const JsonValue* kind = h.find("kind")) {
    if (kind->is_string() && kind->text == "iss") {
      *g = estimator::iss_handrail(static_cast<float>(length));
    } else if (kind->is_string() && kind->text == "round") {
      *g = estimator::paper_round_handrail(static_cast<float>(length));
    } else {
      *error = at(path, *kind) + "\"handrail.kind\" must be \"iss\" or \"round\"";
      return false;
    }
  }
  g->bar_length_m = static_cast<float>(length);
  for (const auto& m : h.members) {
    float* field = m.first == "bar_width_m"               ? &g->bar_width_m
                   : m.first == "bar_depth_m"             ? &g->bar_depth_m
                   : m.first == "bar_center_offset_m"     ? &g->bar_center_offset_m
                   : m.first == "bar_center_offset_min_m" ? &g->bar_center_offset_min_m
                   : m.first == "bar_center_offset_max_m" ? &g->bar_center_offset_max_m
                                                          : nullptr;
    if (m.first == "kind" || m.first == "bar_length_m") continue;
    if (!field) {
      *error = at(path, m.second) + "unknown key \"handrail." + m.first + "\"";
      return false;
    }
    if (!m.second.is_number()) {
      *error = at(path, m.second) + "\"handrail." + m.first + "\" must be a number";
      return false;
    }
    *field = static_cast<float>(m.second.number);
  }
  return true;
}

}  // namespace

bool parse_detector_config(const std::string& text, const std::string& path,
                           estimator::DetectorConfig* cfg, std::string* error) {
  JsonValue root;
  std::string json_error;
  if (!formats::parse_json(text, &root, &json_error)) {
    *error = path + ":" + json_error.substr(5);
    return false;
  }
  return read_detector_config(root, path, cfg, error);
}

bool read_detector_config(const formats::JsonValue& root, const std::string& path,
                          estimator::DetectorConfig* cfg, std::string* error,
                          const std::string& key_prefix) {
  // Keys are named as the file spells them: "estimator.seed" in a section.
  const auto quoted = [&key_prefix](const std::string& key) {
    return "\"" + key_prefix + key + "\"";
  };
  if (!root.is_object()) {
    *error = at(path, root) + "the detector configuration must be a JSON object";
    return false;
  }
  estimator::DetectorConfig c = *cfg;
  for (const auto& m : root.members) {
    const std::string& key = m.first;
    const JsonValue& v = m.second;
    if (key == "handrail") {
      if (!read_handrail(v, path, &c.handrail, error)) {
        if (!key_prefix.empty()) {
          // read_handrail names "handrail.*"; give it the section's prefix.
          const std::size_t q = error->find("\"handrail");
          if (q != std::string::npos) error->insert(q + 1, key_prefix);
        }
        return false;
      }
      continue;
    }
    if (key == "handrail_types") {
      if (!read_handrail_types(v, path, quoted(key), &c, error)) return false;
      continue;
    }
    if (key == "plane_faces_normal" || key == "track_beside" || key == "cross_faces_wall" ||
        key == "bar_first") {
      if (!v.is_bool()) {
        *error = at(path, v) + quoted(key) + " must be true or false";
        return false;
      }
      bool& flag = key == "plane_faces_normal" ? c.plane_faces_normal
                   : key == "track_beside"     ? c.track_beside
                   : key == "bar_first"        ? c.bar_first
                                               : c.cross_faces_wall;
      flag = v.boolean;
      continue;
    }
    bool known = false;
    // The three keys not copied straight into a float or count field, each
    // with its own range: a gripper angle the arm can take (0 to 90 deg,
    // as hrdetect --gripper-angle), a seed that is a whole number, a frame
    // budget of 1 us to 10 s.
    struct Ranged {
      const char* name;
      double lo, hi;
      bool whole;
    };
    static const Ranged kRanged[] = {{"gripper_angle_deg", 0.0, 90.0, false},
                                     {"seed", 0.0, 9007199254740992.0, true},
                                     {"budget_us", 1.0, 1e7, true}};
    for (const Ranged& r : kRanged) {
      if (key != r.name) continue;
      known = true;
      if (!v.is_number() || !(v.number >= r.lo && v.number <= r.hi) ||
          (r.whole && std::floor(v.number) != v.number)) {
        char range[96];
        std::snprintf(range, sizeof range, " must be a %s within %g .. %g",
                      r.whole ? "whole number" : "number", r.lo, r.hi);
        *error = at(path, v) + quoted(key) + range;
        return false;
      }
      if (key == "gripper_angle_deg")
        c.gripper_angle_rad = static_cast<float>(v.number * M_PI / 180.0);
      if (key == "seed") c.seed = static_cast<std::uint64_t>(v.number);
      if (key == "budget_us") c.budget_us = static_cast<std::int64_t>(v.number);
    }
    for (const FloatKey& k : kFloatKeys) {
      if (key != k.name) continue;
      known = true;
      if (!v.is_number()) {
        *error = at(path, v) + quoted(key) + " must be a number";
        return false;
      }
      c.*k.field = static_cast<float>(v.number);
    }
    for (const UintKey& k : kUintKeys) {
      if (key != k.name) continue;
      known = true;
      if (!v.is_number() || v.number < 0 || v.number > 1e7 || std::floor(v.number) != v.number) {
        *error = at(path, v) + quoted(key) + " must be a non-negative integer";
        return false;
      }
      c.*k.field = static_cast<std::uint32_t>(v.number);
    }
    if (!known) {
      *error = at(path, v) + "unknown key " + quoted(key);
      return false;
    }
  }
  if (const char* bad = estimator::validate(c)) {
    const JsonValue* v = root.find(bad);
    *error = path + ":" + std::to_string(v ? v->line : root.line) + ": " + quoted(bad) +
             " is out of range or inconsistent with the other settings";
    return false;
  }
  *cfg = c;
  return true;
}

bool load_detector_config(const std::string& path, estimator::DetectorConfig* cfg,
                          std::string* error) {
  std::string text;
  if (formats::read_file_bounded(path, formats::kMaxTextFileBytes, &text, error) !=
      formats::FileStatus::kOk) {
    return false;
  }
  return parse_detector_config(text, path, cfg, error);
}

}  // namespace estimator
