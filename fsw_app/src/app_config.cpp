#include "fsw_app/app_config.hpp"

#include <cmath>
#include <sstream>

#include "estimator/config_io.hpp"
#include "formats/json.hpp"
#include "formats/text_file.hpp"
#include "hal/use_case.hpp"

namespace fsw_app {
namespace {

using formats::JsonValue;
constexpr double kDeg = M_PI / 180.0;

// Reads the members of one object, naming "section.key" and the line in
// every error.
class Section {
 public:
  Section(const JsonValue& object, std::string name, const std::string& path, std::string* error)
      : object_(object), name_(std::move(name)), path_(path), error_(error) {}

  bool ok() const { return ok_; }
  bool fail(const JsonValue& v, const std::string& key, const std::string& what) {
    if (ok_) *error_ = path_ + ":" + std::to_string(v.line) + ": " + full(key) + ": " + what;
    ok_ = false;
    return false;
  }
  std::string full(const std::string& key) const { return name_.empty() ? key : name_ + "." + key; }
  // Every member must be one of `known`.
  bool only(std::initializer_list<const char*> known) {
    for (const auto& m : object_.members) {
      bool found = false;
      for (const char* k : known) found = found || m.first == k;
      if (!found) return fail(m.second, m.first, "unknown key");
    }
    return ok_;
  }
  void number(const char* key, double* out, double lo, double hi) {
    const JsonValue* v = object_.find(key);
    if (!v || !ok_) return;
    if (!v->is_number()) {
      fail(*v, key, "must be a number");
    } else if (!(v->number >= lo && v->number <= hi)) {
      fail(*v, key, "must be within " + fmt(lo) + " .. " + fmt(hi));
    } else {
      *out = v->number;
    }
  }
  template <typename Int>
  void integer(const char* key, Int* out, double lo, double hi) {
    double d = static_cast<double>(*out);
    const JsonValue* v = object_.find(key);
    number(key, &d, lo, hi);
    if (v && ok_ && std::floor(d) != d) fail(*v, key, "must be a whole number");
    if (ok_) *out = static_cast<Int>(d);
  }
  void text(const char* key, std::string* out) {
    const JsonValue* v = object_.find(key);
    if (!v || !ok_) return;
    if (!v->is_string() || v->text.empty()) {
      fail(*v, key, "must be a non-empty string");
    } else {
      *out = v->text;
    }
  }
  // A fixed-length array of numbers.
  void numbers(const char* key, double* out, int n, double lo, double hi) {
    const JsonValue* v = object_.find(key);
    if (!v || !ok_) return;
    if (!v->is_array() || static_cast<int>(v->items.size()) != n) {
      fail(*v, key, "must be an array of " + std::to_string(n) + " numbers");
      return;
    }
    double tmp[8];
    for (int k = 0; k < n; ++k) {
      const JsonValue& item = v->items[static_cast<std::size_t>(k)];
      if (!item.is_number() || !(item.number >= lo && item.number <= hi)) {
        fail(item, key, "each value must be a number within " + fmt(lo) + " .. " + fmt(hi));
        return;
      }
      tmp[k] = item.number;
    }
    for (int k = 0; k < n; ++k) out[k] = tmp[k];
  }
  const JsonValue* object(const char* key) {
    const JsonValue* v = object_.find(key);
    if (!v || !ok_) return nullptr;
    if (!v->is_object()) {
      fail(*v, key, "must be an object");
      return nullptr;
    }
    return v;
  }
  const JsonValue& self() const { return object_; }

 private:
  static std::string fmt(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
  }
  const JsonValue& object_;
  std::string name_;
  const std::string& path_;
  std::string* error_;
  bool ok_ = true;
};

bool read_limits(Section& s, const char* key, arm::JointLimits* limits) {
  double deg[2] = {limits->min_rad / kDeg, limits->max_rad / kDeg};
  s.numbers(key, deg, 2, -180.0, 180.0);
  if (!s.ok()) return false;
  if (deg[0] >= deg[1]) return s.fail(*s.self().find(key), key, "minimum must be below maximum");
  *limits = {deg[0] * kDeg, deg[1] * kDeg};
  return true;
}

bool read_posture(Section& s, const char* key, arm::JointAngles* q) {
  double deg[2] = {q->tilt_rad / kDeg, q->pan_rad / kDeg};
  s.numbers(key, deg, 2, -180.0, 180.0);
  *q = {deg[0] * kDeg, deg[1] * kDeg};
  return s.ok();
}

}  // namespace

Eigen::Isometry3d AppConfig::default_T_body_cam() {
  Eigen::Matrix3d R;
  // Columns: the camera's x (right), y (down), z (forward) in the body frame.
  R.col(0) = Eigen::Vector3d(0, 1, 0);
  R.col(1) = Eigen::Vector3d(0, 0, -1);
  R.col(2) = Eigen::Vector3d(-1, 0, 0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = Eigen::Vector3d(-0.16, 0.0, 0.06);
  return T;
}

bool parse_app_config(const std::string& text, const std::string& path, AppConfig* config,
                      std::string* error) {
  JsonValue root;
  std::string json_error;
  if (!formats::parse_json(text, &root, &json_error)) {
    *error = path + ":" + json_error.substr(5);
    return false;
  }
  AppConfig c = *config;
  Section top(root, "", path, error);
  if (!root.is_object()) return top.fail(root, "(top)", "the configuration must be a JSON object");
  if (!top.only({"lcm_url", "use_case", "camera", "estimator", "arm", "perch", "servos", "ports",
                 "approach", "arm_rate_hz", "arm_rt_priority", "manager_rate_hz"})) {
    return false;
  }
  top.text("lcm_url", &c.lcm_url);
  top.text("use_case", &c.use_case);
  if (top.ok() && !hal::find_use_case(c.use_case)) {
    return top.fail(*root.find("use_case"), "use_case",
                    "not a Pico Flexx use case (MODE_9_5FPS_2000 ... MODE_5_45FPS_500)");
  }
  top.number("arm_rate_hz", &c.arm_rate_hz, 10.0, 200.0);  // the board's timeout wants >= 10 Hz
  top.integer("arm_rt_priority", &c.arm_rt_priority, 0, 99);
  top.number("manager_rate_hz", &c.manager_rate_hz, 1.0, 200.0);

  if (const JsonValue* v = top.object("camera")) {
    Section s(*v, "camera", path, error);
    if (!s.only({"position_m", "rpy_deg", "serial"})) return false;
    double p[3] = {c.T_body_cam.translation().x(), c.T_body_cam.translation().y(),
                   c.T_body_cam.translation().z()};
    double rpy[3] = {0.0, 0.0, 0.0};
    s.numbers("position_m", p, 3, -2.0, 2.0);
    s.numbers("rpy_deg", rpy, 3, -360.0, 360.0);
    s.text("serial", &c.camera_serial);
    if (s.ok() && c.camera_serial.size() > kCameraSerialChars) {
      return s.fail(*v->find("serial"), "serial",
                    "longer than a Pico Flexx serial number (" +
                        std::to_string(kCameraSerialChars) + " characters)");
    }
    if (!s.ok()) return false;
    c.T_body_cam.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
    if (v->find("rpy_deg")) {
      // Turns of the default aft-looking mount, about the body's axes.
      const Eigen::Matrix3d turn = (Eigen::AngleAxisd(rpy[2] * kDeg, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(rpy[1] * kDeg, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(rpy[0] * kDeg, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
      c.T_body_cam.linear() = turn * AppConfig::default_T_body_cam().linear();
    }
  }
  if (const JsonValue* v = top.object("estimator")) {
    if (!estimator::read_detector_config(*v, path, &c.estimator, error, "estimator.")) return false;
  }
  if (const JsonValue* v = top.object("arm")) {
    Section s(*v, "arm", path, error);
    if (!s.only({"base_m", "proximal_link_m", "distal_link_m", "tilt_limits_deg", "pan_limits_deg",
                 "stow_deg", "deploy_deg", "grip_deg"})) {
      return false;
    }
    arm::ArmGeometry& g = c.perch.geometry;
    double base[3] = {g.p_body_base.x(), g.p_body_base.y(), g.p_body_base.z()};
    s.numbers("base_m", base, 3, -1.0, 1.0);
    g.p_body_base = Eigen::Vector3d(base[0], base[1], base[2]);
    s.number("proximal_link_m", &g.proximal_link_m, 0.01, 1.0);
    s.number("distal_link_m", &g.distal_link_m, 0.01, 1.0);
    if (!read_limits(s, "tilt_limits_deg", &g.tilt) || !read_limits(s, "pan_limits_deg", &g.pan) ||
        !read_posture(s, "stow_deg", &g.stow) || !read_posture(s, "deploy_deg", &g.deploy) ||
        !read_posture(s, "grip_deg", &g.grip)) {
      return false;
    }
    const char* names[] = {"stow_deg", "deploy_deg", "grip_deg"};
    const arm::JointAngles postures[] = {g.stow, g.deploy, g.grip};
    for (int k = 0; k < 3; ++k) {
      if (!arm::within_limits(g, postures[k])) {
        const JsonValue* at = v->find(names[k]);
        return s.fail(at ? *at : *v, names[k], "outside the joint limits");
      }
    }
  }
  if (const JsonValue* v = top.object("perch")) {
    Section s(*v, "perch", path, error);
    if (!s.only({"joint_speed_rad_s",
                 "joint_tolerance_deg",
                 "perched_tilt_limits_deg",
                 "perched_pan_limits_deg",
                 "open_speed",
                 "close_speed",
                 "stow_speed",
                 "close_current_limit_ma",
                 "open_done_counts",
                 "stow_gripper_counts",
                 "stow_gripper_tolerance",
                 "grasp_min_counts",
                 "grasp_max_counts",
                 "grasp_min_current_ma",
                 "grasp_settle_ms",
                 "max_grasp_attempts",
                 "handrail_lost_ms",
                 "pose_lost_ms",
                 "camera_lost_ms",
                 "io_failures_to_fault",
                 "timeouts_ms"})) {
      return false;
    }
    arm::PerchConfig& p = c.perch;
    s.number("joint_speed_rad_s", &p.joint_speed_rad_s, 0.05, 2.1);  // AX-12A: 20 rpm flown
    double tol_deg = p.joint_tolerance_rad / kDeg;
    s.number("joint_tolerance_deg", &tol_deg, 0.3, 20.0);
    p.joint_tolerance_rad = tol_deg * kDeg;
    if (!read_limits(s, "perched_tilt_limits_deg", &p.perched_tilt) ||
        !read_limits(s, "perched_pan_limits_deg", &p.perched_pan)) {
      return false;
    }
    s.number("open_speed", &p.open_speed, 0.05, 1.0);
    s.number("close_speed", &p.close_speed, 0.05, 1.0);
    s.number("stow_speed", &p.stow_speed, 0.05, 1.0);
    s.integer("close_current_limit_ma", &p.close_current_limit_ma, 50, 2500);
    s.integer("open_done_counts", &p.open_done_counts, 0, 8000);
    s.integer("stow_gripper_counts", &p.stow_gripper_counts, 0, 8000);
    s.integer("stow_gripper_tolerance", &p.stow_gripper_tolerance, 1, 2000);
    s.integer("grasp_min_counts", &p.grasp_min_counts, 0, 8000);
    s.integer("grasp_max_counts", &p.grasp_max_counts, 0, 8000);
    s.integer("grasp_min_current_ma", &p.grasp_min_current_ma, 0, 2500);
    s.integer("grasp_settle_ms", &p.grasp_settle_ms, 0, 5000);
    s.integer("max_grasp_attempts", &p.max_grasp_attempts, 1, 10);
    s.integer("handrail_lost_ms", &p.handrail_lost_ms, 100, 60000);
    s.integer("pose_lost_ms", &p.pose_lost_ms, 100, 60000);
    s.integer("camera_lost_ms", &p.camera_lost_ms, 100, 60000);
    s.integer("io_failures_to_fault", &p.io_failures_to_fault, 1, 20);
    if (!s.ok()) return false;
    if (p.grasp_min_counts >= p.grasp_max_counts) {
      return s.fail(v->find("grasp_min_counts") ? *v->find("grasp_min_counts") : *v,
                    "grasp_min_counts", "must be below grasp_max_counts");
    }
    if (const JsonValue* t = s.object("timeouts_ms")) {
      Section ts(*t, "perch.timeouts_ms", path, error);
      if (!ts.only({"init", "deploying", "calibrating", "opening", "gripper_open", "closing",
                    "grasp_check", "pan_tilt", "unperching", "backing_off", "stowing"})) {
        return false;
      }
      arm::StateTimeoutsMs& to = p.timeouts;
      ts.integer("init", &to.init, 100, 600000);
      ts.integer("deploying", &to.deploying, 100, 600000);
      ts.integer("calibrating", &to.calibrating, 100, 600000);
      ts.integer("opening", &to.opening, 100, 600000);
      ts.integer("gripper_open", &to.gripper_open, 100, 3600000);
      ts.integer("closing", &to.closing, 100, 600000);
      ts.integer("grasp_check", &to.grasp_check, 100, 600000);
      ts.integer("pan_tilt", &to.pan_tilt, 100, 600000);
      ts.integer("unperching", &to.unperching, 100, 600000);
      ts.integer("backing_off", &to.backing_off, 100, 3600000);
      ts.integer("stowing", &to.stowing, 100, 600000);
      if (!ts.ok()) return false;
    }
    if (!s.ok()) return false;
  }
  if (const JsonValue* v = top.object("servos")) {
    Section s(*v, "servos", path, error);
    if (!s.only(
            {"tilt_id", "pan_id", "tilt_sign", "pan_sign", "tilt_offset_deg", "pan_offset_deg"})) {
      return false;
    }
    s.integer("tilt_id", &c.servos.tilt_id, 0, 253);
    s.integer("pan_id", &c.servos.pan_id, 0, 253);
    s.integer("tilt_sign", &c.servos.tilt_sign, -1, 1);
    s.integer("pan_sign", &c.servos.pan_sign, -1, 1);
    double off[2] = {c.servos.tilt_offset_rad / kDeg, c.servos.pan_offset_rad / kDeg};
    s.number("tilt_offset_deg", &off[0], -150.0, 150.0);
    s.number("pan_offset_deg", &off[1], -150.0, 150.0);
    if (!s.ok()) return false;
    c.servos.tilt_offset_rad = off[0] * kDeg;
    c.servos.pan_offset_rad = off[1] * kDeg;
    if (c.servos.tilt_sign == 0 || c.servos.pan_sign == 0) {
      return s.fail(*v, "tilt_sign/pan_sign", "must be 1 or -1");
    }
    if (c.servos.tilt_id == c.servos.pan_id) {
      return s.fail(*v, "pan_id", "the two servos need different IDs");
    }
  }
  if (const JsonValue* v = top.object("ports")) {
    Section s(*v, "ports", path, error);
    if (!s.only({"servo_port", "servo_baud", "servo_return_delay_us", "servo_margin_us",
                 "gripper_port", "gripper_baud", "gripper_margin_us",
                 "gripper_serial_timeout_ms"})) {
      return false;
    }
    s.text("servo_port", &c.ports.servo_port);
    s.integer("servo_baud", &c.ports.servo_baud, 1200, 3000000);
    s.integer("servo_return_delay_us", &c.ports.servo_return_delay_us, 0, 508);
    s.integer("servo_margin_us", &c.ports.servo_margin_us, 0, 1000000);
    s.text("gripper_port", &c.ports.gripper_port);
    s.integer("gripper_baud", &c.ports.gripper_baud, 1200, 3000000);
    s.integer("gripper_margin_us", &c.ports.gripper_margin_us, 0, 1000000);
    // The arm polls the board every cycle: at least two cycles at 10 Hz.
    s.integer("gripper_serial_timeout_ms", &c.ports.gripper_serial_timeout_ms, 200, 16000);
    if (!s.ok()) return false;
  }
  if (const JsonValue* v = top.object("approach")) {
    Section s(*v, "approach", path, error);
    if (!s.only({"standoff_m", "max_speed_mps", "max_rate_rps", "gain_per_s",
                 "integral_gain_per_s2", "brake_mps2", "settle_speed_mps", "position_tolerance_m",
                 "angle_tolerance_deg", "back_off_m", "settle_cycles", "pose_max_age_ms",
                 "pose_max_position_sigma_m", "pose_max_attitude_sigma_deg",
                 "camera_hold_frames"})) {
      return false;
    }
    ApproachConfig& a = c.approach;
    s.number("standoff_m", &a.standoff_m, 0.0, 2.0);
    s.number("max_speed_mps", &a.max_speed_mps, 0.005, 0.5);
    s.number("max_rate_rps", &a.max_rate_rps, 0.01, 2.0);
    s.number("gain_per_s", &a.gain_per_s, 0.05, 10.0);
    s.number("integral_gain_per_s2", &a.integral_gain_per_s2, 0.0, 10.0);
    s.number("brake_mps2", &a.brake_mps2, 0.001, 1.0);
    s.number("settle_speed_mps", &a.settle_speed_mps, 0.0005, 0.1);
    s.number("position_tolerance_m", &a.position_tolerance_m, 0.001, 0.1);
    double deg = a.angle_tolerance_rad / kDeg;
    s.number("angle_tolerance_deg", &deg, 0.1, 30.0);
    a.angle_tolerance_rad = deg * kDeg;
    s.number("back_off_m", &a.back_off_m, 0.05, 2.0);
    s.integer("settle_cycles", &a.settle_cycles, 1, 1000);
    s.integer("pose_max_age_ms", &a.pose_max_age_ms, 20, 5000);
    s.number("pose_max_position_sigma_m", &a.pose_max_position_sigma_m, 0.005, 10.0);
    double sigma_deg = a.pose_max_attitude_sigma_rad / kDeg;
    s.number("pose_max_attitude_sigma_deg", &sigma_deg, 0.1, 180.0);
    a.pose_max_attitude_sigma_rad = sigma_deg * kDeg;
    s.integer("camera_hold_frames", &a.camera_hold_frames, 2, 100);
    if (!s.ok()) return false;
  }
  if (!top.ok()) return false;
  // The manager's frame-age bound is in frame periods of this use case.
  c.approach.frame_period_us = hal::frame_period_us(*hal::find_use_case(c.use_case));
  *config = c;
  return true;
}

bool load_app_config(const std::string& path, AppConfig* config, std::string* error) {
  std::string text;
  if (formats::read_file_bounded(path, formats::kMaxTextFileBytes, &text, error) !=
      formats::FileStatus::kOk) {
    return false;
  }
  return parse_app_config(text, path, config, error);
}

}  // namespace fsw_app
