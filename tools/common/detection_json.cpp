#include "detection_json.hpp"

#include <algorithm>
#include <cstdio>

namespace tools {
namespace {

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out;
}

std::string vec(const Eigen::Vector3f& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "[%.5f,%.5f,%.5f]", v.x(), v.y(), v.z());
  return buf;
}

}  // namespace

std::string detection_to_json(const std::string& frame, const estimator::HandrailDetection& d) {
  char time_ms[32];
  std::snprintf(time_ms, sizeof time_ms, "%.3f", d.processing_time_us / 1000.0);
  std::string s = "{\"frame\":\"" + escape(frame) +
                  "\",\"frame_id\":" + std::to_string(d.frame_id) + ",\"state\":\"" +
                  to_string(d.state) + "\"";
  if (d.status == estimator::DetectStatus::kFound) {
    s += ",\"position\":" + vec(d.p_cam_center);
    s += ",\"axis\":" + vec(d.axis());
    s += ",\"normal\":" + vec(d.normal());
    s += ",\"ends\":[";
    bool first = true;
    for (int e = 0; e < 2; ++e) {
      if (!d.end_seen[e]) continue;
      if (!first) s += ",";
      s += vec(d.ends_cam[e]);
      first = false;
    }
    s += "],\"target_position\":" + vec(d.p_cam_target);
    s += ",\"target_rotation\":[";
    for (int r = 0; r < 3; ++r) {
      if (r) s += ",";
      s += vec(d.R_cam_target.row(r).transpose());
    }
    s += "],\"inliers\":" + std::to_string(d.inliers);
    char lengths[160];
    std::snprintf(lengths, sizeof lengths,
                  ",\"visible_length_m\":%.4f,\"length_m\":%.4f,\"mount_offset_m\":%.4f",
                  d.visible_length_m, d.length_m, d.mount_offset_m);
    s += lengths;
    // The ISS type a bar seen end to end matches; null when its ends are not
    // both in view (its length is then unknown) or it matches none.
    s += ",\"iss_type\":";
    s += d.handrail_type_name ? "\"" + escape(d.handrail_type_name) + "\"" : std::string("null");
  } else {
    s += ",\"reason\":\"" + std::string(to_string(d.status)) + "\"";
    if (d.status == estimator::DetectStatus::kNoLine) {
      s += ",\"first_line\":\"" + std::string(to_string(d.counts.first_rejection)) + "\"";
    }
  }
  s += ",\"mounts\":{\"found\":" + std::to_string(d.counts.mount_hypotheses) +
       ",\"tried\":" + std::to_string(d.counts.mounts_tried) + "}";
  s += ",\"time_ms\":" + std::string(time_ms) + "}";
  return s;
}

std::string mounts_to_json(const estimator::Plane& dominant, const estimator::MountHypotheses& m) {
  auto metres = [](const float* v, std::uint32_t n) {
    std::string s = "[";
    for (std::uint32_t k = 0; k < n; ++k) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%s%.4f", k ? "," : "", v[k]);
      s += buf;
    }
    return s + "]";
  };
  const std::uint32_t surfaces = std::min(m.surface_count, estimator::kMaxSurfacePeaks);
  const std::uint32_t mounts = std::min(m.count, estimator::kMaxMountHypotheses);
  char d_m[32];
  std::snprintf(d_m, sizeof d_m, "%.4f", dominant.d);
  std::string s = "{\"plane\":{\"normal\":" + vec(dominant.normal) + ",\"d_m\":" + d_m + "}";
  s += ",\"surfaces_m\":" + metres(m.surface_m, surfaces);
  s += ",\"offsets_m\":" + metres(m.offset_m, mounts);
  s += ",\"front_pixels\":[";
  for (std::uint32_t k = 0; k < mounts; ++k) {
    s += (k ? "," : "") + std::to_string(m.front_pixels[k]);
  }
  s += "],\"plane_front_pixels\":" + std::to_string(m.dominant_front_pixels);
  // The last this many of offsets_m were read off bar-front peaks.
  s += ",\"front_peak_mounts\":" + std::to_string(std::min(m.front_peak_count, mounts)) + "}";
  return s;
}

std::string line_trace_to_json(const estimator::LineTrace& trace) {
  std::string s = "[";
  const std::uint32_t n = std::min(trace.count, estimator::LineTrace::kMaxEntries);
  for (std::uint32_t k = 0; k < n; ++k) {
    const estimator::LineTraceEntry& e = trace.entries[k];
    char head[160];
    std::snprintf(head, sizeof head,
                  "%s{\"search\":%u,\"search_mount_m\":%.4f,\"verdict\":\"%s\",\"inliers\":%u",
                  k ? "," : "", static_cast<unsigned>(e.search), e.search_mount_m,
                  to_string(e.verdict), e.inliers);
    s += head;
    if (e.has_center_line) {
      char lengths[128];
      s += ",\"middle\":" + vec(e.middle_cam) + ",\"axis\":" + vec(e.axis_cam);
      if (e.seated) {
        std::snprintf(lengths, sizeof lengths,
                      ",\"visible_length_m\":%.4f,\"front_m\":%.4f,\"mount_m\":%.4f",
                      e.visible_length_m, e.front_height_m, e.mount_m);
      } else {
        std::snprintf(lengths, sizeof lengths,
                      ",\"visible_length_m\":%.4f,\"front_above_search_m\":%.4f",
                      e.visible_length_m, e.front_height_m);
      }
      s += lengths;
    }
    if (e.ends_walked) {
      s += std::string(",\"ends_seen\":[") + (e.end_seen[0] ? "true" : "false") + "," +
           (e.end_seen[1] ? "true" : "false") + "]";
    }
    s += "}";
  }
  return s + "]";
}

const estimator::LineTraceEntry* best_supported_line(const estimator::LineTrace& trace) {
  const std::uint32_t n = std::min(trace.count, estimator::LineTrace::kMaxEntries);
  const estimator::LineTraceEntry* best = nullptr;
  for (std::uint32_t k = 0; k < n; ++k) {
    if (!best || trace.entries[k].inliers > best->inliers) best = &trace.entries[k];
  }
  return best;
}

std::string best_line_to_json(const estimator::LineTraceEntry* best) {
  if (!best) return "null";
  const estimator::LineTraceEntry& e = *best;
  // Until seated, trace_line measures the front above the searched mount.
  const float mount_m = e.has_center_line ? e.mount_m : e.search_mount_m;
  char head[160];
  std::snprintf(head, sizeof head,
                "{\"search\":%u,\"mount_m\":%.4f,\"verdict\":\"%s\",\"inliers\":%u",
                static_cast<unsigned>(e.search), mount_m, to_string(e.verdict), e.inliers);
  std::string s = head;
  if (!e.has_center_line) {
    return s +
           ",\"middle_cam\":null,\"axis_cam\":null,\"visible_length_m\":null,"
           "\"front_height_m\":null}";
  }
  char lengths[96];
  std::snprintf(lengths, sizeof lengths, ",\"visible_length_m\":%.4f,\"front_height_m\":%.4f}",
                e.visible_length_m, e.front_height_m);
  return s + ",\"middle_cam\":" + vec(e.middle_cam) + ",\"axis_cam\":" + vec(e.axis_cam) + lengths;
}

std::string with_line_trace(std::string object, const estimator::LineTrace& trace) {
  object.pop_back();  // the closing brace
  object += ",\"lines\":" + line_trace_to_json(trace);
  if (trace.dropped > 0) object += ",\"lines_not_kept\":" + std::to_string(trace.dropped);
  return object + "}";
}

std::string track_to_json(const estimator::TrackedHandrail& t) {
  std::string s = "{\"event\":\"" + std::string(to_string(t.event)) + "\"";
  if (t.valid) {
    s += ",\"state\":\"" + std::string(to_string(t.state)) + "\"";
    s += ",\"position\":" + vec(t.p_world_center);
    s += ",\"axis\":" + vec(t.R_world_handrail.col(2));
    s += ",\"normal\":" + vec(t.R_world_handrail.col(0));
    s += ",\"target_position\":" + vec(t.p_world_target);
  }
  return s + "}";
}

}  // namespace tools
