#pragma once
// A small deterministic world for the localization tests: a robot moving
// smoothly in a plane (x, y, yaw) in front of a vertical handrail on a wall,
// as in the paper's granite-table test, and the measurements the filter
// would get: IMU samples with white noise and drifting biases, GP poses with
// a slowly drifting bias of a few cm and about 1 deg, white noise and 100 to
// 300 ms of latency, and handrail detections (BE, OE or NE by what the
// camera's 62 x 45 deg field of view holds) with features on the bar and the
// wall, from the true relative pose with point noise and detection noise.
// Fixed seeds: every run gives the same numbers on one platform.
//
// World: the wall is the plane x = 0, facing +x. The handrail frame is the
// world's axes (x = wall normal toward the robot, z = along the bar, up),
// origin on the bar's centre line 0.061 m off the wall (the ISS bar, 0.55 m
// long). The body's x axis points away from the wall at yaw 0, so the camera
// (looking along body -x, localization::default_T_body_cam()) faces it.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "estimator/localization/config.hpp"
#include "estimator/localization/localization_filter.hpp"
#include "estimator/localization/measurements.hpp"
#include "estimator/localization/so3.hpp"

namespace locsim {

using namespace estimator::localization;
using estimator::HandrailState;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

struct Truth {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();  // world, body origin
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // world from body
  Eigen::Vector3d omega_body = Eigen::Vector3d::Zero();
  Eigen::Isometry3d T() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q.toRotationMatrix();
    T.translation() = p;
    return T;
  }
};

// x(t) = smooth step from x_start to x_end over [t_move_start, t_move_end]
//        + ax sin(wx t);  y(t) = ay sin(wy t + phy);  z constant;
// yaw(t) = ayaw sin(wyaw t + phyaw). Everything analytic.
struct Trajectory {
  double x_start = 1.0, x_end = 1.0;
  double t_move_start = 0.0, t_move_end = 1.0;
  double ax = 0.04, wx = 2 * kPi / 17.0;
  double ay = 0.08, wy = 2 * kPi / 23.0, phy = 0.4;
  double z = -0.06;  // puts the camera (0.06 above the body) at the bar's centre height
  double ayaw = 6 * kDeg, wyaw = 2 * kPi / 19.0, phyaw = 1.0;

  Truth at(double t) const {
    double s = 0.0, ds = 0.0, dds = 0.0;
    const double T = t_move_end - t_move_start;
    if (t >= t_move_end) {
      s = 1.0;
    } else if (t > t_move_start) {
      const double u = (t - t_move_start) / T;
      s = u * u * u * (10 - 15 * u + 6 * u * u);
      ds = 30 * u * u * (1 - u) * (1 - u) / T;
      dds = (60 * u - 180 * u * u + 120 * u * u * u) / (T * T);
    }
    const double L = x_end - x_start;
    Truth tr;
    tr.p = {x_start + L * s + ax * std::sin(wx * t), ay * std::sin(wy * t + phy), z};
    tr.v = {L * ds + ax * wx * std::cos(wx * t), ay * wy * std::cos(wy * t + phy), 0.0};
    tr.a = {L * dds - ax * wx * wx * std::sin(wx * t), -ay * wy * wy * std::sin(wy * t + phy), 0.0};
    const double yaw = ayaw * std::sin(wyaw * t + phyaw);
    tr.q = Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
    tr.omega_body = {0.0, 0.0, ayaw * wyaw * std::cos(wyaw * t + phyaw)};
    return tr;
  }
};

struct SimConfig {
  std::uint64_t seed = 1;
  double duration_s = 40.0;
  Trajectory traj;
  Eigen::Isometry3d T_body_cam = default_T_body_cam();
  // IMU (62.5 Hz): white noise densities, bias random walks, initial biases.
  double imu_rate_hz = 62.5;
  double gyro_noise = 5e-5, accel_noise = 1e-3;
  double gyro_bias_rw = 5e-7, accel_bias_rw = 5e-5;
  Eigen::Vector3d gyro_bias0{0.002, -0.0015, 0.001};
  Eigen::Vector3d accel_bias0{0.01, -0.006, 0.008};
  // GP localizer.
  bool gp = true;
  double gp_rate_hz = 1.5;
  double gp_latency_min_s = 0.10, gp_latency_max_s = 0.30;
  double gp_bias_m = 0.03, gp_bias_rad = 1.0 * kDeg;  // amplitude of the slow drift
  double gp_white_m = 0.005, gp_white_rad = 0.3 * kDeg;
  double gp_sigma_m = 0.03, gp_sigma_rad = 1.5 * kDeg;  // what it reports
  double gp_stop_s = std::numeric_limits<double>::infinity();
  // Handrail detections (5 Hz).
  bool handrail = true;
  double handrail_start_s = 0.0;
  double handrail_rate_hz = 5.0;
  double handrail_latency_min_s = 0.06, handrail_latency_max_s = 0.15;
  double point_noise_m = 0.003;
  double detect_pos_noise_m = 0.0015, detect_rot_noise_rad = 0.3 * kDeg;
  int bar_points = 40, wall_points = 20;
};

struct Event {
  enum Kind { kGp, kHandrail } kind = kGp;
  double arrival_s = 0.0;
  double capture_s = 0.0;
  int order = 0;  // made in this order
  GpPose gp;
  HandrailMeasurement hr;
};

inline std::int64_t to_us(double t_s) {
  return static_cast<std::int64_t>(std::llround(t_s * 1e6));
}

class Sim {
 public:
  explicit Sim(const SimConfig& c) : c_(c), rng_(c.seed) {
    T_world_handrail_.setIdentity();
    T_world_handrail_.translation() = Eigen::Vector3d(0.061, 0.0, 0.0);
    make_imu();
    if (c_.gp) make_gp();
    if (c_.handrail) make_handrail();
    // By arrival, ties in the order made. (std::sort with the tie broken, not
    // std::stable_sort: that one's buffer comes from the nothrow operator
    // new, which tests/support/allocation_counter.hpp does not replace.)
    for (std::size_t i = 0; i < events_.size(); ++i) events_[i].order = static_cast<int>(i);
    std::sort(events_.begin(), events_.end(), [](const Event& a, const Event& b) {
      return a.arrival_s < b.arrival_s || (a.arrival_s == b.arrival_s && a.order < b.order);
    });
  }

  const SimConfig& config() const { return c_; }
  const std::vector<ImuSample>& imu() const { return imu_; }
  const std::vector<Event>& events() const { return events_; }
  Truth truth(double t) const { return c_.traj.at(t); }
  const Eigen::Isometry3d& T_world_handrail() const { return T_world_handrail_; }

  // The GP's bias at t (position, attitude): slow sines of a few cm and ~1 deg.
  Eigen::Vector3d gp_bias_p(double t) const {
    const double b = c_.gp_bias_m;
    return {b * std::sin(0.11 * t + 0.3), 0.8 * b * std::sin(0.07 * t + 1.1),
            0.6 * b * std::sin(0.05 * t + 2.0)};
  }
  Eigen::Vector3d gp_bias_theta(double t) const {
    const double b = c_.gp_bias_rad;
    return {0.6 * b * std::sin(0.09 * t), 0.5 * b * std::sin(0.06 * t + 1.0),
            b * std::sin(0.04 * t + 0.5)};
  }

  // A handrail detection at capture time t from the true pose; an offset in
  // the camera frame moves the whole measurement (points and pose).
  bool detect(double t, HandrailMeasurement* m,
              const Eigen::Vector3d& offset_cam = Eigen::Vector3d::Zero()) {
    const Eigen::Isometry3d T_world_cam = truth(t).T() * c_.T_body_cam;
    const Eigen::Isometry3d T_cam_handrail = T_world_cam.inverse() * T_world_handrail_;
    const double half = 0.275;
    // The visible part of the bar's centre line, in 1 cm steps.
    double lo = 1e9, hi = -1e9;
    for (int i = 0; i <= 55; ++i) {
      const double z = -half + 0.01 * i;
      if (in_view(T_cam_handrail * Eigen::Vector3d(0, 0, z))) {
        lo = std::min(lo, z);
        hi = std::max(hi, z);
      }
    }
    if (hi < lo || hi - lo < 0.08) return false;
    const bool end_lo = in_view(T_cam_handrail * Eigen::Vector3d(0, 0, -half));
    const bool end_hi = in_view(T_cam_handrail * Eigen::Vector3d(0, 0, half));
    m->capture_time_us = to_us(t);
    m->state = end_lo && end_hi   ? HandrailState::kBothEnds
               : end_lo || end_hi ? HandrailState::kOneEnd
                                  : HandrailState::kNoEnd;
    // The detected frame: the true one with noise, its origin along the bar
    // at the centre when an end is seen, else at the visible part's middle
    // (the detector cannot tell where along the bar it is).
    Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
    delta.linear() = quat_exp(gauss3(c_.detect_rot_noise_rad)).toRotationMatrix();
    delta.translation() = gauss3(c_.detect_pos_noise_m);
    if (m->state == HandrailState::kNoEnd) delta.translation().z() += 0.5 * (lo + hi);
    Eigen::Isometry3d shift = Eigen::Isometry3d::Identity();
    shift.translation() = offset_cam;
    m->T_cam_handrail = shift * T_cam_handrail * delta;
    m->num_features = 0;
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    Eigen::Vector3d pts[kMaxInputFeatures];
    for (int i = 0; i < c_.bar_points; ++i) {
      const Eigen::Vector3d h(0.0175, 0.016 * (u01(rng_) - 0.5), lo + (hi - lo) * u01(rng_));
      pts[i] = T_cam_handrail * h + gauss3(c_.point_noise_m) + offset_cam;
    }
    add_features(pts, c_.bar_points, FeatureKind::kBar, m);
    for (int i = 0; i < c_.wall_points; ++i) {
      const double side = i % 2 == 0 ? 1.0 : -1.0;
      const Eigen::Vector3d h(-0.061, side * (0.03 + 0.15 * u01(rng_)),
                              lo - 0.05 + (hi - lo + 0.1) * u01(rng_));
      pts[i] = T_cam_handrail * h + gauss3(c_.point_noise_m) + offset_cam;
    }
    add_features(pts, c_.wall_points, FeatureKind::kWall, m);
    return true;
  }

  // The true pose of the body in the handrail frame, and the filter's (its
  // pose in the frame of its handrail map, or of the true handrail without
  // one): what perching needs.
  Eigen::Vector3d true_p_handrail_body(double t) const {
    return T_world_handrail_.inverse() * truth(t).p;
  }

  std::mt19937_64& rng() { return rng_; }

 private:
  static bool in_view(const Eigen::Vector3d& p_cam) {
    if (p_cam.z() < 0.1) return false;
    return std::fabs(std::atan2(p_cam.x(), p_cam.z())) < 30.0 * kDeg &&
           std::fabs(std::atan2(p_cam.y(), p_cam.z())) < 21.5 * kDeg;
  }

  Eigen::Vector3d gauss3(double sigma) {
    std::normal_distribution<double> n(0.0, sigma);
    return {n(rng_), n(rng_), n(rng_)};
  }

  void make_imu() {
    const double dt = 1.0 / c_.imu_rate_hz;
    const int n = static_cast<int>(c_.duration_s * c_.imu_rate_hz) + 1;
    Eigen::Vector3d bg = c_.gyro_bias0, ba = c_.accel_bias0;
    imu_.reserve(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) {
      const double t = k * dt;
      const Truth tr = truth(t);
      ImuSample s;
      s.t_us = to_us(t);
      s.omega_body_radps = tr.omega_body + bg + gauss3(c_.gyro_noise / std::sqrt(dt));
      s.a_body_mps2 = tr.q.conjugate() * tr.a + ba + gauss3(c_.accel_noise / std::sqrt(dt));
      imu_.push_back(s);
      bg += gauss3(c_.gyro_bias_rw * std::sqrt(dt));
      ba += gauss3(c_.accel_bias_rw * std::sqrt(dt));
    }
  }

  void make_gp() {
    std::uniform_real_distribution<double> lat(c_.gp_latency_min_s, c_.gp_latency_max_s);
    std::uniform_real_distribution<double> jitter(-0.02, 0.02);
    for (double t = 0.25; t < c_.duration_s && t < c_.gp_stop_s; t += 1.0 / c_.gp_rate_hz) {
      const double tc = t + jitter(rng_);
      const Truth tr = truth(tc);
      Event e;
      e.kind = Event::kGp;
      e.capture_s = tc;
      e.arrival_s = tc + lat(rng_);
      e.gp.capture_time_us = to_us(tc);
      e.gp.p_world_body_m = tr.p + gp_bias_p(tc) + gauss3(c_.gp_white_m);
      e.gp.q_world_body = quat_exp(gp_bias_theta(tc) + gauss3(c_.gp_white_rad)) * tr.q;
      e.gp.cov.setZero();
      e.gp.cov.topLeftCorner<3, 3>() = c_.gp_sigma_m * c_.gp_sigma_m * Eigen::Matrix3d::Identity();
      e.gp.cov.bottomRightCorner<3, 3>() =
          c_.gp_sigma_rad * c_.gp_sigma_rad * Eigen::Matrix3d::Identity();
      events_.push_back(e);
    }
  }

  void make_handrail() {
    std::uniform_real_distribution<double> lat(c_.handrail_latency_min_s,
                                               c_.handrail_latency_max_s);
    for (double t = c_.handrail_start_s + 0.1; t < c_.duration_s; t += 1.0 / c_.handrail_rate_hz) {
      Event e;
      e.kind = Event::kHandrail;
      e.capture_s = t;
      e.arrival_s = t + lat(rng_);
      if (detect(t, &e.hr)) events_.push_back(e);
    }
  }

  SimConfig c_;
  std::mt19937_64 rng_;
  Eigen::Isometry3d T_world_handrail_;
  std::vector<ImuSample> imu_;
  std::vector<Event> events_;
};

// The filter's estimate of the body position in the handrail frame: in its
// map's frame when it has one, else in the true handrail's (GP-only).
inline Eigen::Vector3d estimated_p_handrail_body(const LocalizationFilter& f, const Sim& sim) {
  const HandrailMap map = f.handrail_map();
  const Eigen::Isometry3d T = map.valid ? map.T_world_handrail : sim.T_world_handrail();
  return T.inverse() * f.state().p_world_body_m;
}

// A filter configuration matching the simulated sensors.
inline LocalizationConfig sim_filter_config(const SimConfig& s) {
  LocalizationConfig c;
  c.T_body_cam = s.T_body_cam;
  c.imu_rate_hz = s.imu_rate_hz;
  c.imu.gyro_noise_radps_rthz = 2.0 * s.gyro_noise;
  c.imu.accel_noise_mps2_rthz = 2.0 * s.accel_noise;
  c.imu.gyro_bias_rw_radps2_rthz = 2.0 * s.gyro_bias_rw;
  c.imu.accel_bias_rw_mps3_rthz = 2.0 * s.accel_bias_rw;
  return c;
}

// Runs the simulation through the filter: every IMU sample in order (but
// those drop(k) says are missing), and after each the measurements of
// `events` that have arrived by then. on_step(k, t_s) after each sample
// (missing ones too); on_event(event, status) after each measurement.
template <class OnStep, class OnEvent, class Drop>
void run_events(const Sim& sim, const std::vector<Event>& events, LocalizationFilter& f,
                OnStep&& on_step, OnEvent&& on_event, Drop&& drop, int end_sample = -1) {
  const std::vector<ImuSample>& imu = sim.imu();
  std::size_t next = 0;
  const int end = end_sample < 0 ? static_cast<int>(imu.size()) : end_sample;
  for (int k = 0; k < end; ++k) {
    const ImuSample& s = imu[static_cast<std::size_t>(k)];
    if (!drop(k)) f.add_imu(s);
    const double t = 1e-6 * static_cast<double>(s.t_us);
    while (next < events.size() && events[next].arrival_s <= t) {
      const Event& e = events[next++];
      const UpdateStatus st = e.kind == Event::kGp ? f.add_gp_pose(e.gp) : f.add_handrail(e.hr);
      on_event(e, st);
    }
    on_step(k, t);
  }
}

template <class OnStep, class OnEvent>
void run(const Sim& sim, LocalizationFilter& f, OnStep&& on_step, OnEvent&& on_event,
         int end_sample = -1) {
  run_events(
      sim, sim.events(), f, on_step, on_event, [](int) { return false; }, end_sample);
}

// The IMU sample index at time t.
inline int sample_at(const Sim& sim, double t_s) {
  return static_cast<int>(std::lround(t_s * sim.config().imu_rate_hz));
}

}  // namespace locsim
