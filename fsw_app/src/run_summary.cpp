#include "run_summary.hpp"

#include <signal.h>

#include <string>

namespace fsw_app {

const char* signal_name(int sig) {
  switch (sig) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    default:
      return "a signal";
  }
}

namespace {

// The share of the processed pixels that came out valid (-1: none).
double valid_pixel_share(const pico_flexx::PipelineCounts& c) {
  std::uint64_t all = 0;
  for (std::uint64_t n : c.pixels_by_state) all += n;
  if (all == 0) return -1.0;
  return static_cast<double>(c.pixels_by_state[static_cast<int>(tof::PixelState::kValid)]) /
         static_cast<double>(all);
}

// The USB path: what the driver delivered and lost, and what it recovered from.
void print_usb(const UsbPathReport& u, std::FILE* out) {
  const pico_flexx::UsbCounters& d = u.driver;
  std::fprintf(
      out,
      "  USB                 %llu frames delivered, %llu lost (%llu not sent, %llu "
      "refused)%s; %llu unplugs, %llu replugs, %llu stalls, %llu clear halts, %llu "
      "re-initialisations, %llu resets, %llu command timeouts; camera %s\n",
      static_cast<unsigned long long>(d.frames_delivered),
      static_cast<unsigned long long>(u.frames_lost),
      static_cast<unsigned long long>(u.frames_not_sent),
      static_cast<unsigned long long>(u.frames_refused),
      u.frames_made_by_camera >= 0
          ? (", of " + std::to_string(u.frames_made_by_camera) + " the camera made").c_str()
          : "",
      static_cast<unsigned long long>(d.unplugs), static_cast<unsigned long long>(d.replugs),
      static_cast<unsigned long long>(d.stalls), static_cast<unsigned long long>(d.clear_halts),
      static_cast<unsigned long long>(d.reinitialisations),
      static_cast<unsigned long long>(d.usb_resets),
      static_cast<unsigned long long>(d.command_timeouts), u.state.c_str());
}

void write_usb_json(const UsbPathReport& u, std::FILE* f) {
  const pico_flexx::UsbCounters& d = u.driver;
  std::fprintf(
      f,
      ", \"frames_lost\": %llu, \"usb\": {\"frames_delivered\": %llu, \"frames_not_sent\": "
      "%llu, \"frames_refused\": %llu, \"frames_short\": %llu, \"frames_corrupt\": %llu, "
      "\"frames_made_by_camera\": %lld, \"unplugs\": %llu, \"replugs\": %llu, "
      "\"stalls\": %llu, \"silences\": %llu, \"clear_halts\": %llu, "
      "\"reinitialisations\": %llu, \"usb_resets\": %llu, \"command_timeouts\": %llu, "
      "\"transfers_failed\": %llu, \"reacquisitions\": %llu, \"state\": \"%s\", "
      "\"health\": \"%s\"}",
      static_cast<unsigned long long>(u.frames_lost),
      static_cast<unsigned long long>(d.frames_delivered),
      static_cast<unsigned long long>(u.frames_not_sent),
      static_cast<unsigned long long>(u.frames_refused),
      static_cast<unsigned long long>(d.assembly.frames_short),
      static_cast<unsigned long long>(d.assembly.frames_corrupt),
      static_cast<long long>(u.frames_made_by_camera), static_cast<unsigned long long>(d.unplugs),
      static_cast<unsigned long long>(d.replugs), static_cast<unsigned long long>(d.stalls),
      static_cast<unsigned long long>(d.silences), static_cast<unsigned long long>(d.clear_halts),
      static_cast<unsigned long long>(d.reinitialisations),
      static_cast<unsigned long long>(d.usb_resets),
      static_cast<unsigned long long>(d.command_timeouts),
      static_cast<unsigned long long>(d.transfers_failed),
      static_cast<unsigned long long>(d.reacquisitions), u.state.c_str(), u.health.c_str());
}

// The camera through the royale API: what royale handed on.
void print_royale(const RoyalePathReport& r, std::FILE* out) {
  std::fprintf(
      out,
      "  royale              %llu frames delivered, %llu malformed, %llu before a "
      "listener%s; capture times %s\n",
      static_cast<unsigned long long>(r.frames.delivered),
      static_cast<unsigned long long>(r.frames.malformed),
      static_cast<unsigned long long>(r.frames.unattended),
      r.frames_made_by_camera >= 0
          ? (", of " + std::to_string(r.frames_made_by_camera) + " the camera made").c_str()
          : "",
      r.capture_clock == "SAME"     ? "on this host's clock"
      : r.capture_clock == "MAPPED" ? "mapped from the camera's clock"
                                    : "unknown (no frame)");
}

void write_royale_json(const RoyalePathReport& r, std::FILE* f) {
  std::fprintf(f,
               ", \"royale\": {\"frames_delivered\": %llu, \"frames_malformed\": %llu, "
               "\"frames_unattended\": %llu, \"frames_made_by_camera\": %lld, "
               "\"capture_clock\": \"%s\"}",
               static_cast<unsigned long long>(r.frames.delivered),
               static_cast<unsigned long long>(r.frames.malformed),
               static_cast<unsigned long long>(r.frames.unattended),
               static_cast<long long>(r.frames_made_by_camera), r.capture_clock.c_str());
}

// Which path the frames took and, on the raw path, what processing cost.
void print_camera(const RunSummary& s, std::FILE* out) {
  if (s.camera_path.empty()) return;
  if (!s.tof) {
    std::fprintf(out, "  camera path         %s\n", s.camera_path.c_str());
  } else {
    const pico_flexx::PipelineCounts& c = *s.tof;
    std::fprintf(out,
                 "  camera path         %s: ToF processing median %.2f ms over %llu frames, %llu "
                 "dropped, %llu mostly invalid, %.1f %% of pixels valid\n",
                 s.camera_path.c_str(), 1e-3 * static_cast<double>(s.tof_median_us),
                 static_cast<unsigned long long>(c.frames_in),
                 static_cast<unsigned long long>(c.frames_dropped),
                 static_cast<unsigned long long>(c.frames_mostly_invalid),
                 100.0 * valid_pixel_share(c));
  }
  if (s.usb) print_usb(*s.usb, out);
  if (s.royale) print_royale(*s.royale, out);
}

// The camera as the perch manager judged it: how often frames went late
// (the robot held), for how long in all, and the longest gap.
void print_camera_watch(const RunSummary& s, std::FILE* out) {
  if (!s.camera_watch) return;
  const CameraWatch& w = *s.camera_watch;
  std::fprintf(out,
               "  camera watch        %u late spells (held %.1f s in all), longest gap between "
               "frames %.0f ms; %s at the end\n",
               w.late_spells, 1e-6 * static_cast<double>(w.late_us),
               1e-3 * static_cast<double>(w.longest_frame_gap_us), to_string(w.liveness));
}

void write_camera_watch_json(const RunSummary& s, std::FILE* f) {
  const CameraWatch w = s.camera_watch.value_or(CameraWatch{});
  std::fprintf(f,
               ", \"watch\": {\"status\": \"%s\", \"late_spells\": %lld, \"late_ms\": %.1f, "
               "\"longest_frame_gap_ms\": %.1f}",
               s.camera_watch ? to_string(w.liveness) : "",
               s.camera_watch ? static_cast<long long>(w.late_spells) : -1LL,
               s.camera_watch ? 1e-3 * static_cast<double>(w.late_us) : -1.0,
               s.camera_watch ? 1e-3 * static_cast<double>(w.longest_frame_gap_us) : -1.0);
}

void write_camera_json(const RunSummary& s, std::FILE* f) {
  const pico_flexx::PipelineCounts c = s.tof.value_or(pico_flexx::PipelineCounts{});
  const long long none = -1;
  std::fprintf(f,
               "\"camera\": {\"path\": \"%s\", \"tof_median_us\": %lld, \"tof_frames\": %lld, "
               "\"tof_frames_dropped\": %lld, \"tof_frames_mostly_invalid\": %lld, "
               "\"tof_valid_pixel_share\": %.4f",
               s.camera_path.c_str(), static_cast<long long>(s.tof_median_us),
               s.tof ? static_cast<long long>(c.frames_in) : none,
               s.tof ? static_cast<long long>(c.frames_dropped) : none,
               s.tof ? static_cast<long long>(c.frames_mostly_invalid) : none,
               s.tof ? valid_pixel_share(c) : -1.0);
  if (s.usb) write_usb_json(*s.usb, f);
  if (s.royale) write_royale_json(*s.royale, f);
  write_camera_watch_json(s, f);
  std::fputs("}, ", f);
}

void print_frames(const RunSummary& s, std::FILE* out) {
  const hrp::estimator_health_t& h = s.health;
  std::fprintf(
      out, "  frames              %lld received, %lld processed, %lld dropped, %lld corrupt\n",
      static_cast<long long>(h.frames_received), static_cast<long long>(h.frames_processed),
      static_cast<long long>(h.frames_dropped), static_cast<long long>(h.frames_corrupt));
  std::fprintf(out,
               "  deadline misses     %lld (budget %d us; processing median %d us, max %d us)\n",
               static_cast<long long>(h.deadline_misses), h.budget_us, h.processing_median_us,
               h.processing_max_us);
  print_camera(s, out);
  print_camera_watch(s, out);
  if (s.camera_longest_gap_ms >= 0.0) {
    std::fprintf(out, "  frame pipeline      longest gap between frames %.0f ms",
                 s.camera_longest_gap_ms);
    if (s.estimator_longest_latency_ms >= 0.0) {
      std::fprintf(out, ", longest capture to estimate %.0f ms", s.estimator_longest_latency_ms);
    }
    if (s.estimator_frames_without_pose >= 0) {
      std::fprintf(out, ", %lld without a pose at capture", s.estimator_frames_without_pose);
      if (!s.without_pose_reasons.empty()) {
        std::fprintf(out, " (%s)", s.without_pose_reasons.c_str());
      }
    }
    std::fprintf(out, "\n");
  }
}

// What the estimator reported, frame by frame: the states, and for the
// frames with both ends seen the length range and the ISS types matched.
void print_sightings(const RunSummary& s, std::FILE* out) {
  if (!s.sightings) return;
  const SightingCounts& c = s.sightings->counts;
  std::fprintf(out, "  sightings           BE %llu",
               static_cast<unsigned long long>(c.by_state[1]));
  if (c.by_state[1] > 0) {
    std::fprintf(out, " (%.2f to %.2f m:", c.be_length_min_m, c.be_length_max_m);
    const char* sep = " ";
    for (std::uint32_t k = 0; k <= estimator::kMaxHandrailTypes; ++k) {
      if (c.be_by_type[k] == 0) continue;
      const bool named = k < s.sightings->type_count;
      std::fprintf(out, "%s%s %llu", sep, named ? s.sightings->type_names[k] : "no type",
                   static_cast<unsigned long long>(c.be_by_type[k]));
      sep = ", ";
    }
    std::fprintf(out, ")");
  }
  std::fprintf(out, ", OE %llu, NE %llu, none %llu", static_cast<unsigned long long>(c.by_state[2]),
               static_cast<unsigned long long>(c.by_state[3]),
               static_cast<unsigned long long>(c.by_state[0]));
  if (c.rejected > 0) {
    std::fprintf(out, ", %llu refused", static_cast<unsigned long long>(c.rejected));
  }
  std::fprintf(out, "\n");
}

// One line for the checked inputs; a line per channel that refused any.
void print_inputs(const RunSummary& s, std::FILE* out) {
  const hrp::input_health_t& in = s.inputs;
  long long accepted = 0, rejected = 0;
  for (int k = 0; k < in.num_channels; ++k) {
    accepted += in.accepted[k];
    for (int r = 0; r < in.num_reasons; ++r) rejected += in.rejected[k][r];
  }
  std::fprintf(out, "  inputs              %lld messages accepted, %lld rejected on %d channels\n",
               accepted, rejected, in.num_channels);
  for (int k = 0; k < in.num_channels; ++k) {
    long long any = 0;
    for (int r = 0; r < in.num_reasons; ++r) any += in.rejected[k][r];
    if (any == 0) continue;
    std::fprintf(out, "    %-17s %lld rejected:", in.channel[k].c_str(), any);
    for (int r = 0; r < in.num_reasons; ++r) {
      if (in.rejected[k][r]) {
        std::fprintf(out, " %s %lld", in.reason[r].c_str(),
                     static_cast<long long>(in.rejected[k][r]));
      }
    }
    std::fprintf(out, "\n");
  }
  if (s.receiver_faults > 0) {
    std::fprintf(out, "    %llu exceptions from receivers contained by the hub\n",
                 static_cast<unsigned long long>(s.receiver_faults));
  }
}

std::uint64_t handrail_updates(const LocalizerReport& r) {
  return r.task.handrail_accepted_be + r.task.handrail_accepted_oe + r.task.handrail_accepted_ne;
}

// The filter's error against the truth beside the GP localizer's, and what
// the filter made of its inputs.
void print_localization(const RunSummary& s, std::FILE* out) {
  if (s.localization) {
    const LocalizationScore& l = *s.localization;
    const PoseErrorStats &f = l.filter_approach, &g = l.gp_approach;
    std::fprintf(out,
                 "  pose error          approach: filter mean %.1f mm max %.1f mm, %.2f / %.2f "
                 "deg; GP mean %.1f mm max %.1f mm, %.2f / %.2f deg\n",
                 1e3 * f.mean_m, 1e3 * f.max_m, f.mean_deg, f.max_deg, 1e3 * g.mean_m,
                 1e3 * g.max_m, g.mean_deg, g.max_deg);
    const NeesStats& n = l.filter_nees_approach;
    if (n.samples > 0) {
      std::fprintf(out,
                   "  filter NEES         approach: position mean %.1f max %.1f, attitude mean "
                   "%.1f max %.1f (3 each when consistent; %lld poses)\n",
                   n.mean_position, n.max_position, n.mean_attitude, n.max_attitude,
                   static_cast<long long>(n.samples));
    }
    if (l.at_grasp) {
      std::fprintf(out,
                   "                      at grasp: filter %.1f mm %.2f deg; GP %.1f mm %.2f deg\n",
                   1e3 * l.filter_grasp_m, l.filter_grasp_deg, 1e3 * l.gp_grasp_m, l.gp_grasp_deg);
    }
  }
  if (s.localizer) {
    const LocalizerReport& r = *s.localizer;
    std::fprintf(out,
                 "  localizer           IMU %u propagated, %u gaps bridged, %u lost, %u "
                 "rejected; GP %u accepted, %llu held off, %u gated, %u jump, %u relocalized; "
                 "handrail %u + "
                 "%u NE accepted, %u gated, %u other rejections, %u features gated%s\n"
                 "  handrail updates    %llu BE, %llu OE, %llu NE accepted; %llu OE taken as NE "
                 "(bar length not yet known)%s\n",
                 r.imu_propagated, r.imu_gaps_bridged, r.imu_gaps_lost, r.imu_rejected,
                 r.gp_accepted, static_cast<unsigned long long>(r.task.gp_held_off),
                 r.gp_rejected_gate, r.gp_rejected_jump, r.gp_relocalized, r.handrail_accepted,
                 r.handrail_no_end_accepted, r.handrail_rejected_gate, r.handrail_rejected_other,
                 r.features_gated, r.map_valid ? "; handrail map held" : "",
                 static_cast<unsigned long long>(r.task.handrail_accepted_be),
                 static_cast<unsigned long long>(r.task.handrail_accepted_oe),
                 static_cast<unsigned long long>(r.task.handrail_accepted_ne),
                 static_cast<unsigned long long>(r.task.handrail_oe_as_ne),
                 s.perched && handrail_updates(r) == 0 ? "; PERCHED WITH NO HANDRAIL UPDATE" : "");
  }
}

void print_log(const Options& opt, const RunSummary& s, std::FILE* out) {
  if (opt.log.empty()) return;
  std::fprintf(out, "  LCM log             %s (%lld messages", opt.log.c_str(),
               static_cast<long long>(s.log_messages));
  if (s.frames_published >= 0) {
    std::fprintf(out, "; %lld of %lld depth frames", static_cast<long long>(s.log_depth_frames),
                 static_cast<long long>(s.frames_published));
  }
  std::fprintf(out, ")\n");
  if (!s.log_failure.empty()) {
    std::fprintf(out, "  LCM log FAILED      %s; %lld messages not recorded\n",
                 s.log_failure.c_str(), static_cast<long long>(s.log_lost));
  }
}

}  // namespace

void print_perch_summary(const Options& opt, const RunSummary& s, std::FILE* out) {
  const bool fault = s.arm.state == hrp::arm_state_t::FAULT;
  std::fprintf(out, "summary\n");
  std::fprintf(
      out, "  result              %s\n",
      s.stop.stopped ? "STOPPED" : (s.perched ? "PERCHED" : (fault ? "FAULT" : "TIMEOUT")));
  if (s.stop.stopped) {
    std::fprintf(out, "  stopped by          %s; %s after %.1f s\n", signal_name(s.stop.signal),
                 s.stop.at_rest ? "the arm came to rest" : "the arm did NOT come to rest",
                 s.stop.after_s);
  }
  std::fprintf(out, "  arm state           %s%s%s\n", s.arm.state_name.c_str(),
               s.arm.fault_text.empty() ? "" : ": ", s.arm.fault_text.c_str());
  if (s.perched) std::fprintf(out, "  time to perch       %.1f s after PERCH\n", s.time_to_perch_s);
  if (s.grasp_error_m >= 0.0) {
    std::fprintf(out,
                 "  gripper to bar      %.1f mm when the grip closed, %.1f mm along the bar "
                 "from its middle\n",
                 s.grasp_error_m * 1000.0, s.grasp_along_m * 1000.0);
  }
  print_frames(s, out);
  print_sightings(s, out);
  if (s.arm_loop) {
    const CycleStats& a = *s.arm_loop;
    std::fprintf(out,
                 "  arm loop            %lld cycles, %lld overruns, longest gap %.0f ms, "
                 "longest cycle %.0f ms, real-time %s\n",
                 static_cast<long long>(a.cycles), static_cast<long long>(a.overruns),
                 1e-3 * static_cast<double>(a.longest_gap_us),
                 1e-3 * static_cast<double>(a.longest_cycle_us), hal::to_string(a.realtime));
  }
  if (s.servo_bus) {
    const dynamixel::BusCounters& bc = *s.servo_bus;
    std::fprintf(out,
                 "  servo bus           %u transactions, %u retries, %u timeouts, %u bad "
                 "checksums\n",
                 bc.transactions, bc.retries, bc.timeouts, bc.bad_checksums);
  }
  if (s.gripper_retries)
    std::fprintf(out, "  gripper board       %u retries\n", *s.gripper_retries);
  print_localization(s, out);
  print_inputs(s, out);
  print_log(opt, s, out);
}

void print_replay_summary(const Options& opt, const RunSummary& s, std::FILE* out) {
  std::fprintf(out, "summary\n");
  if (s.replay) {
    const LogPlayerCounts& r = *s.replay;
    std::fprintf(out,
                 "  replayed            %s: %llu frames (%llu would not decode), %llu robot "
                 "poses; %llu other messages not played\n",
                 opt.frames_from_log.c_str(), static_cast<unsigned long long>(r.frames),
                 static_cast<unsigned long long>(r.bad_frames),
                 static_cast<unsigned long long>(r.poses),
                 static_cast<unsigned long long>(r.other));
    if (r.damaged > 0) {
      std::fprintf(out,
                   "  damaged log         %llu stretches of bytes that were no event skipped "
                   "(each costs the event before it)\n",
                   static_cast<unsigned long long>(r.damaged));
    }
  }
  print_frames(s, out);
  print_sightings(s, out);
  print_inputs(s, out);
  print_log(opt, s, out);
}

namespace {

// A string for a JSON document: the arm's state and fault texts come off
// the bus and may hold anything a sender put there.
std::string json_escaped(const std::string& text) {
  std::string out;
  out.reserve(text.size() + 8);
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (u < 0x20 || u >= 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\u%04x", u);
      out += hex;
    } else {
      out += c;
    }
  }
  return out;
}

// "inputs": {"CHANNEL": {"accepted": n, "rejected": {"REASON": n, ...}}, ...}
void write_inputs_json(const hrp::input_health_t& in, std::FILE* f) {
  std::fprintf(f, "\"inputs\": {");
  for (int k = 0; k < in.num_channels; ++k) {
    std::fprintf(f, "%s\"%s\": {\"accepted\": %lld, \"rejected\": {", k ? ", " : "",
                 in.channel[k].c_str(), static_cast<long long>(in.accepted[k]));
    for (int r = 0; r < in.num_reasons; ++r) {
      std::fprintf(f, "%s\"%s\": %lld", r ? ", " : "", in.reason[r].c_str(),
                   static_cast<long long>(in.rejected[k][r]));
    }
    std::fprintf(f, "}}");
  }
  std::fprintf(f, "}");
}

void write_errors_json(const char* name, const PoseErrorStats& e, std::FILE* f) {
  std::fprintf(f,
               "\"%s\": {\"samples\": %lld, \"mean_m\": %.5f, \"max_m\": %.5f, \"mean_deg\": %.3f, "
               "\"max_deg\": %.3f}",
               name, static_cast<long long>(e.samples), e.mean_m, e.max_m, e.mean_deg, e.max_deg);
}

// "sightings": {"nh", "be", "oe", "ne", "rejected", "be_length_min_m",
// "be_length_max_m", "be_types": {name: count, ..., "none": count}}; null
// without an estimator's results here.
void write_sightings_json(const RunSummary& s, std::FILE* f) {
  if (!s.sightings) {
    std::fprintf(f, "\"sightings\": null, ");
    return;
  }
  const SightingCounts& c = s.sightings->counts;
  std::fprintf(f,
               "\"sightings\": {\"nh\": %llu, \"be\": %llu, \"oe\": %llu, \"ne\": %llu, "
               "\"rejected\": %llu, \"be_length_min_m\": %.4f, \"be_length_max_m\": %.4f, "
               "\"be_types\": {",
               static_cast<unsigned long long>(c.by_state[0]),
               static_cast<unsigned long long>(c.by_state[1]),
               static_cast<unsigned long long>(c.by_state[2]),
               static_cast<unsigned long long>(c.by_state[3]),
               static_cast<unsigned long long>(c.rejected), c.be_length_min_m, c.be_length_max_m);
  for (std::uint32_t k = 0; k < s.sightings->type_count; ++k) {
    std::fprintf(f, "\"%s\": %llu, ", s.sightings->type_names[k],
                 static_cast<unsigned long long>(c.be_by_type[k]));
  }
  std::fprintf(f, "\"none\": %llu}}, ",
               static_cast<unsigned long long>(c.be_by_type[estimator::kMaxHandrailTypes]));
}

// "localization": {"approach": {"filter": {...}, "gp": {...}}, "grasp": {...},
// "filter": {counts}}; absent parts are null.
void write_localization_json(const RunSummary& s, std::FILE* f) {
  std::fprintf(f, "\"localization\": {");
  if (s.localization) {
    const LocalizationScore& l = *s.localization;
    std::fprintf(f, "\"approach\": {");
    write_errors_json("filter", l.filter_approach, f);
    std::fprintf(f, ", ");
    write_errors_json("gp", l.gp_approach, f);
    const NeesStats& n = l.filter_nees_approach;
    std::fprintf(f,
                 ", \"filter_nees\": {\"samples\": %lld, \"position_mean\": %.3f, "
                 "\"position_max\": %.3f, \"attitude_mean\": %.3f, \"attitude_max\": %.3f}",
                 static_cast<long long>(n.samples), n.mean_position, n.max_position,
                 n.mean_attitude, n.max_attitude);
    std::fprintf(f,
                 "}, \"grasp\": {\"filter_m\": %.5f, \"filter_deg\": %.3f, \"gp_m\": %.5f, "
                 "\"gp_deg\": %.3f}, \"filter_poses\": %lld, \"non_filter_poses\": %lld, ",
                 l.filter_grasp_m, l.filter_grasp_deg, l.gp_grasp_m, l.gp_grasp_deg,
                 static_cast<long long>(l.filter_poses),
                 static_cast<long long>(l.non_filter_poses));
  } else {
    std::fprintf(f, "\"approach\": null, \"grasp\": null, ");
  }
  if (s.localizer) {
    const LocalizerReport& r = *s.localizer;
    std::fprintf(f,
                 "\"filter\": {\"initialized\": %s, \"map_valid\": %s, \"imu_propagated\": %u, "
                 "\"imu_gaps_bridged\": %u, \"imu_gaps_lost\": %u, \"imu_rejected\": %u, "
                 "\"imu_seq_gaps\": %llu, \"gp_accepted\": %u, \"gp_held_off\": %llu, "
                 "\"gp_rejected_gate\": %u, "
                 "\"gp_rejected_jump\": %u, \"gp_relocalized\": %u, \"gp_rejected_other\": %u, "
                 "\"handrail_accepted\": %u, \"handrail_no_end_accepted\": %u, "
                 "\"handrail_rejected_gate\": %u, \"handrail_rejected_other\": %u, "
                 "\"handrail_unusable\": %llu, \"features_gated\": %u, \"map_resets\": %u, "
                 "\"poses_published\": %llu, \"map_surveyed\": %s, \"handrail_holding\": %s, "
                 "\"gp_fallback_accepted\": %llu, \"position_sigma_m\": %.5f, "
                 "\"position_sigma_held_min_m\": %.5f, \"across_bar_sigma_m\": %.5f, "
                 "\"across_bar_sigma_held_min_m\": %.5f, \"handrail_accepted_be\": %llu, "
                 "\"handrail_accepted_oe\": %llu, \"handrail_accepted_ne\": %llu, "
                 "\"handrail_oe_as_ne\": %llu}",
                 r.initialized ? "true" : "false", r.map_valid ? "true" : "false", r.imu_propagated,
                 r.imu_gaps_bridged, r.imu_gaps_lost, r.imu_rejected,
                 static_cast<unsigned long long>(r.task.imu_seq_gaps), r.gp_accepted,
                 static_cast<unsigned long long>(r.task.gp_held_off), r.gp_rejected_gate,
                 r.gp_rejected_jump, r.gp_relocalized, r.gp_rejected_other, r.handrail_accepted,
                 r.handrail_no_end_accepted, r.handrail_rejected_gate, r.handrail_rejected_other,
                 static_cast<unsigned long long>(r.task.handrail_unusable), r.features_gated,
                 r.map_resets, static_cast<unsigned long long>(r.task.poses_published),
                 r.map_surveyed ? "true" : "false", r.handrail_holding ? "true" : "false",
                 static_cast<unsigned long long>(r.task.gp_fallback_accepted),
                 r.task.position_sigma_m, r.task.position_sigma_held_min_m,
                 r.task.across_bar_sigma_m, r.task.across_bar_sigma_held_min_m,
                 static_cast<unsigned long long>(r.task.handrail_accepted_be),
                 static_cast<unsigned long long>(r.task.handrail_accepted_oe),
                 static_cast<unsigned long long>(r.task.handrail_accepted_ne),
                 static_cast<unsigned long long>(r.task.handrail_oe_as_ne));
  } else {
    std::fprintf(f, "\"filter\": null");
  }
  std::fprintf(f, "}, ");
}

}  // namespace

bool write_summary_json(const Options& opt, const RunSummary& s, const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  const hrp::estimator_health_t& h = s.health;
  const CycleStats arm = s.arm_loop.value_or(CycleStats{-1, -1, -1000, -1000});
  std::fprintf(
      f,
      "{\"seed\": %llu, \"scenario\": \"%s\", \"tasks\": \"%s\", \"perched\": %s, "
      "\"success\": %s, \"arm_state\": \"%s\", \"fault\": \"%s\", \"fault_text\": \"%s\", "
      "\"arm_tilt_rad\": %.3f, \"arm_pan_rad\": %.3f, \"receiver_faults\": %llu, "
      "\"time_to_perch_s\": %.2f, \"grasp_error_m\": %.4f, \"grasp_along_m\": %.4f, "
      "\"frames_received\": %lld, "
      "\"frames_processed\": %lld, \"frames_dropped\": %lld, \"frames_corrupt\": %lld, "
      "\"deadline_misses\": %lld, \"processing_median_us\": %d, \"arm_cycles\": %lld, "
      "\"arm_overruns\": %lld, \"arm_longest_gap_ms\": %.1f, \"arm_realtime\": \"%s\", "
      "\"camera_longest_gap_ms\": %.1f, \"estimator_longest_latency_ms\": %.1f, "
      "\"estimator_frames_without_pose\": %lld, \"estimator_without_pose_by_reason\": %s, "
      "\"replayed_frames\": %lld, \"replayed_bad_frames\": %lld, \"replay_damaged\": %lld, ",
      static_cast<unsigned long long>(opt.seed), json_escaped(opt.scenario).c_str(),
      task_names(opt.tasks).c_str(), s.perched ? "true" : "false", s.success ? "true" : "false",
      json_escaped(s.arm.state_name).c_str(), json_escaped(s.arm.fault_name).c_str(),
      json_escaped(s.arm.fault_text).c_str(), s.arm.tilt_rad, s.arm.pan_rad,
      static_cast<unsigned long long>(s.receiver_faults), s.time_to_perch_s, s.grasp_error_m,
      s.grasp_along_m, static_cast<long long>(h.frames_received),
      static_cast<long long>(h.frames_processed), static_cast<long long>(h.frames_dropped),
      static_cast<long long>(h.frames_corrupt), static_cast<long long>(h.deadline_misses),
      h.processing_median_us, static_cast<long long>(arm.cycles),
      static_cast<long long>(arm.overruns), 1e-3 * static_cast<double>(arm.longest_gap_us),
      s.arm_loop ? hal::to_string(arm.realtime) : "", s.camera_longest_gap_ms,
      s.estimator_longest_latency_ms, s.estimator_frames_without_pose,
      s.without_pose_reasons_json.c_str(),
      s.replay ? static_cast<long long>(s.replay->frames) : -1LL,
      s.replay ? static_cast<long long>(s.replay->bad_frames) : -1LL,
      s.replay ? static_cast<long long>(s.replay->damaged) : -1LL);
  std::fprintf(f,
               "\"log_messages\": %lld, \"log_depth_frames\": %lld, \"frames_published\": %lld, "
               "\"log_failure\": \"%s\", \"log_lost\": %lld, \"stopped\": %s, \"stop_signal\": %d, "
               "\"stopped_at_rest\": %s, ",
               static_cast<long long>(s.log_messages), static_cast<long long>(s.log_depth_frames),
               static_cast<long long>(s.frames_published), json_escaped(s.log_failure).c_str(),
               static_cast<long long>(s.log_lost), s.stop.stopped ? "true" : "false", s.stop.signal,
               s.stop.at_rest ? "true" : "false");
  write_camera_json(s, f);
  write_sightings_json(s, f);
  write_localization_json(s, f);
  write_inputs_json(s.inputs, f);
  std::fprintf(f, "}\n");
  return std::fclose(f) == 0;
}

}  // namespace fsw_app
