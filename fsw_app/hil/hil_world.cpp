#include "hil_world.hpp"

#include <cmath>
#include <limits>

#include "fsw_app/msg_convert.hpp"
#include "sim_hal/sim_random.hpp"

namespace fsw_app {
namespace {

constexpr double kDeg = M_PI / 180.0;
// The simulated board's encoder: the open stop at raw -500 (0 counts after
// calibration), the fingers meeting at 3000 counts; open they span 8 cm.
constexpr int kOpenStopRaw = -500;
constexpr int kClosedCounts = 3000;
constexpr double kOpenSpanM = 0.08;
// Within this of the bar's centre line the closing fingers take the bar
// (the gripper's own tolerance is larger; the requirement is 1 cm).
constexpr double kCaptureRadiusM = 0.03;

double bar_width_m(const sim_hal::Handrail& h) {
  return h.kind == sim_hal::HandrailKind::kPaperRound ? 0.035 : 0.019;
}

}  // namespace

Eigen::Isometry3d hil_start_pose(const sim_hal::Scenario& scenario,
                                 const Eigen::Isometry3d& T_body_cam, std::uint64_t seed) {
  const Eigen::Isometry3d T_world_cam0 = scenario.T_world_cam.front();
  Eigen::Isometry3d T_world_body = T_world_cam0 * T_body_cam.inverse();
  sim_hal::SimRandom rng(seed * 7919 + 17);
  const auto spread = [&](double half) { return (2.0 * rng.uniform() - 1.0) * half; };
  // The wall normal from the nearest handrail, else the camera's view.
  Eigen::Vector3d normal = -T_world_cam0.linear().col(2);
  Eigen::Vector3d foot = T_world_cam0.translation() + normal * -1.0;
  if (!scenario.scene.handrails.empty()) {
    normal = scenario.scene.handrails.front().normal.normalized();
    foot = scenario.scene.handrails.front().foot_center;
  }
  Eigen::Vector3d across = normal.cross(Eigen::Vector3d::UnitZ());
  if (across.norm() < 1e-6) across = Eigen::Vector3d::UnitY();
  across.normalize();
  const Eigen::Vector3d up = across.cross(normal).normalized();
  const double out_now = normal.dot(T_world_body.translation() - foot);
  const double out_want = 0.9 + 0.2 * rng.uniform() + 0.40;  // camera 0.9..1.1 m out
  T_world_body.translation() +=
      (out_want - out_now) * normal + spread(0.10) * across + spread(0.05) * up;
  const Eigen::Matrix3d turn =
      (Eigen::AngleAxisd(spread(8.0) * kDeg, up) * Eigen::AngleAxisd(spread(4.0) * kDeg, across) *
       Eigen::AngleAxisd(spread(4.0) * kDeg, normal))
          .toRotationMatrix();
  T_world_body.linear() = turn * T_world_body.linear();
  return T_world_body;
}

HilWorld::HilWorld(LcmHub& hub, const sim_hal::Scenario& scenario, const AppConfig& config,
                   const Eigen::Isometry3d& T_world_body_start, std::uint64_t seed,
                   const hal::Clock& clock, const HilSensorParams& sensors)
    : hub_(hub),
      scenario_(scenario),
      config_(config),
      clock_(clock),
      servos_({config.servos.tilt_id, config.servos.pan_id}, seed),
      camera_(scenario, clock, sim_hal::SimulatedCamera::Pacing::kRealTime),
      flyer_(T_world_body_start, sim_hal::FlyerParams{}, seed),
      sensors_(hub, sensors, seed) {
  // The target: the handrail nearest the start's line of sight.
  const Eigen::Isometry3d T_world_cam = T_world_body_start * config.T_body_cam;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < scenario.scene.handrails.size(); ++k) {
    const sim_hal::Handrail& h = scenario.scene.handrails[k];
    const Eigen::Vector3d c = 0.5 * (h.end_point(0) + h.end_point(1));
    const Eigen::Vector3d d = c - T_world_cam.translation();
    const Eigen::Vector3d z = T_world_cam.linear().col(2);
    const double off_axis = (d - d.dot(z) * z).norm();
    if (off_axis < best) {
      best = off_axis;
      target_ = k;
    }
  }
  const double width = scenario.scene.handrails.empty() ? 0.0 : bar_width_m(target_handrail());
  handrail_counts_ = static_cast<int>(std::lround(kClosedCounts * (1.0 - width / kOpenSpanM)));
  hub_.subscribe(channel::kBodyVelocityCommand, &command_box_);
  // Left stowed.
  servos_.set_position(config.servos.tilt_id,
                       config.servos.tilt_sign * config.perch.geometry.stow.tilt_rad +
                           config.servos.tilt_offset_rad);
  servos_.set_position(
      config.servos.pan_id,
      config.servos.pan_sign * config.perch.geometry.stow.pan_rad + config.servos.pan_offset_rad);
  camera_.set_pose_source(this);
  camera_.set_tamper(this);
}

HilWorld::~HilWorld() {
  stop();
}

bool HilWorld::start(std::string* error) {
  if (scenario_.scene.handrails.empty()) {
    *error = scenario_.name + ": the scenario has no handrail to perch on";
    return false;
  }
  if (!servos_.start(error) || !gripper_.start(error)) return false;
  physics_.start(10000, [this] { physics_tick(); });
  return true;
}

void HilWorld::stop() {
  (void)camera_.stop_capture();
  physics_.stop();
  servos_.stop();
  gripper_.stop();
}

Eigen::Isometry3d HilWorld::body_pose() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return flyer_.pose();
}

Eigen::Isometry3d HilWorld::T_world_cam(std::int64_t) {
  return body_pose() * config_.T_body_cam;
}

void HilWorld::tamper(std::int64_t now_us, hal::DepthFrame* frame,
                      std::vector<hal::DepthPoint>* points) {
  if (now_us < occluded_until_us_.load()) {
    for (hal::DepthPoint& p : *points) p = {0.0f, 0.0f, 0.0f, 0.0f, 0, 0};
  }
  if (corrupt_frames_.load() > 0) {
    corrupt_frames_.fetch_sub(1);
    frame->width = 0;  // a header the camera task must refuse
  }
}

arm::JointAngles HilWorld::joint_angles() const {
  sim_hal::SimServo tilt, pan;
  arm::JointAngles q;
  if (servos_.servo(config_.servos.tilt_id, &tilt)) {
    q.tilt_rad = config_.servos.tilt_sign * (tilt.position_rad() - config_.servos.tilt_offset_rad);
  }
  if (servos_.servo(config_.servos.pan_id, &pan)) {
    q.pan_rad = config_.servos.pan_sign * (pan.position_rad() - config_.servos.pan_offset_rad);
  }
  return q;
}

void HilWorld::bar_distance(const Eigen::Vector3d& p, double* perp_m, double* along_m) const {
  const sim_hal::Handrail& h = target_handrail();
  const Eigen::Vector3d a = h.end_point(0), b = h.end_point(1);
  const Eigen::Vector3d axis = (b - a).normalized();
  const double t = (p - a).dot(axis);
  *along_m = t;
  *perp_m = (p - a - t * axis).norm();
}

double HilWorld::gripper_to_bar_m() const {
  const Eigen::Isometry3d T_world_grasp =
      body_pose() * arm::forward_kinematics(config_.perch.geometry, joint_angles());
  double perp = 0.0, along = 0.0;
  bar_distance(T_world_grasp.translation(), &perp, &along);
  return perp;
}

HilStats HilWorld::stats() const {
  HilStats s;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    s = stats_;
  }
  s.localization = sensors_.score();
  return s;
}

void HilWorld::physics_tick() {
  const std::int64_t now = clock_.now_us();
  const double dt = last_tick_us_ > 0 ? 1e-6 * static_cast<double>(now - last_tick_us_) : 0.0;
  last_tick_us_ = now;
  bool locked_before = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    locked_before = stats_.locked;
  }
  physics_step(dt, now);
  Eigen::Isometry3d T;
  Eigen::Vector3d v, w;
  bool locked = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    T = flyer_.pose();
    v = flyer_.velocity();
    w = flyer_.angular_velocity();
    locked = stats_.locked;
  }
  // The truth at half the physics rate (50 Hz), the sensors every tick.
  sensors_.on_tick(now, T, v, w, ++ticks_ % 2 == 0);
  if (locked && !locked_before) sensors_.mark_grasp();
}

void HilWorld::physics_step(double dt_s, std::int64_t now_us) {
  hrp::body_velocity_command_t cmd{};
  Eigen::Vector3d v = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
  // A stale command (the manager stopped) means hold still.
  if (command_box_.read(&cmd) != 0 && now_us - cmd.utime < 500000 && !cmd.hold) {
    v = Eigen::Vector3d(cmd.velocity_mps[0], cmd.velocity_mps[1], cmd.velocity_mps[2]);
    w = Eigen::Vector3d(cmd.angular_velocity_rps[0], cmd.angular_velocity_rps[1],
                        cmd.angular_velocity_rps[2]);
  }
  const arm::JointAngles q = joint_angles();
  const Eigen::Isometry3d T_body_grasp = arm::forward_kinematics(config_.perch.geometry, q);
  const sim_hal::GripperSnapshot g = gripper_.snapshot();
  const int handrail_raw = kOpenStopRaw + handrail_counts_;
  std::lock_guard<std::mutex> lock(mutex_);
  if (stats_.locked) {
    // Held: the body hangs on the grasp, turned by the joints.
    const bool released = g.position_raw < handrail_raw - 150;
    if (!released) {
      flyer_.hold_at(T_world_grasp_lock_ * T_body_grasp.inverse());
      return;
    }
    stats_.locked = false;
  }
  flyer_.step(dt_s, v, w);
  const Eigen::Isometry3d T_world_grasp = flyer_.pose() * T_body_grasp;
  double perp = 0.0, along = 0.0;
  bar_distance(T_world_grasp.translation(), &perp, &along);
  const sim_hal::Handrail& h = target_handrail();
  const double length = (h.end_point(1) - h.end_point(0)).norm();
  // The link must point into the wall for the fingers to reach round the bar.
  const bool facing =
      T_world_grasp.linear().col(0).dot(-h.normal.normalized()) > std::cos(25 * kDeg);
  const bool within = perp < kCaptureRadiusM && along > 0.02 && along < length - 0.02 && facing;
  // Fingers already past the bar's place cannot take it any more.
  const bool open_enough = g.position_raw < handrail_raw - 50;
  gripper_.set_handrail_raw(
      within && (open_enough || g.position_raw <= handrail_raw + 2) ? handrail_raw : -1);
  if (within && g.position_raw >= handrail_raw - 5 && g.current_a > 0.3) {
    // The grip closed on the bar: record how far off it was, then the
    // fingers centre the bar (the body moves by that error) and hold.
    stats_.locked = true;
    if (stats_.grasp_error_m < 0.0) {
      stats_.grasp_error_m = perp;
      stats_.grasp_along_m = along - 0.5 * length;
      stats_.locked_at_us = now_us;
    }
    const Eigen::Vector3d a = h.end_point(0);
    const Eigen::Vector3d axis = (h.end_point(1) - a).normalized();
    T_world_grasp_lock_ = T_world_grasp;
    T_world_grasp_lock_.translation() = a + along * axis;
    flyer_.hold_at(T_world_grasp_lock_ * T_body_grasp.inverse());
  }
}

}  // namespace fsw_app
