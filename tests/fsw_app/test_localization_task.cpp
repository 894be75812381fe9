// The localization task in lock step on simulated time, over real LCM
// (memq://): the simulated IMU and general-purpose localizer
// (hil/hil_sensors.hpp) driven by a simulated free-flyer, handrail
// estimates made from the true pose as the estimator task publishes them,
// and the task's ROBOT_POSE scored against the truth. The faults at task
// level: the handrail lost (the filter falls back on the GP and its
// covariance grows), the IMU silent for 0.5 s, a handrail estimate 5 cm
// off (gated, counted), the GP jumping 20 cm (rejected while the handrail
// holds the pose), NaN on every input (rejected at the hub, counted, the
// filter untouched). And the channel lists: no robot-side task subscribes
// to the truth.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "cmocka_cpp.hpp"
#include "fsw_app/camera_task.hpp"
#include "fsw_app/estimator_task.hpp"
#include "fsw_app/frame_ring.hpp"
#include "fsw_app/localization_task.hpp"
#include "fsw_app/msg_convert.hpp"
#include "fsw_app/perch_manager.hpp"
#include "hal/clock.hpp"
#include "hil_sensors.hpp"
#include "sim_hal/flyer.hpp"
#include "sim_hal/sim_random.hpp"

namespace {

namespace loc = estimator::localization;

class SimClock final : public hal::Clock {
 public:
  std::int64_t now_us() const override { return t_us; }
  std::int64_t t_us = 1000000;
};

// The wall is the plane x = 0 facing +x; the handrail frame has x = wall
// normal, z = along the bar (vertical), origin 6.1 cm off the wall.
Eigen::Isometry3d world_handrail() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.061, 0.0, 0.0);
  return T;
}

// The body 0.8 m out, its camera (looking along body -x by the default
// mount) facing the wall.
Eigen::Isometry3d start_pose() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.8, 0.0, -0.06);
  return T;
}

struct Rig {
  SimClock clock;
  fsw_app::LcmHub hub{"memq://", clock};
  fsw_app::HilSensors sensors;
  fsw_app::LocalizationTaskConfig cfg;
  fsw_app::LocalizationTask task;
  sim_hal::SimFlyer flyer;
  sim_hal::SimRandom rng;
  fsw_app::Publisher<hrp::handrail_estimate_t> estimate_pub{hub,
                                                            fsw_app::channel::kHandrailEstimate};
  fsw_app::Mailbox<hrp::robot_pose_t> pose_box;
  hrp::robot_pose_t pose{};
  bool handrail_on = true;
  // The bar's true length, and whether the detector sees only its top end
  // (OE: the origin in the middle of the 0.3 m seen below that end).
  double bar_length_m = 0.55;
  bool one_end = false;
  Eigen::Vector3d handrail_offset_cam = Eigen::Vector3d::Zero();
  std::int64_t next_frame_us = 0;
  std::int64_t frame_id = 0;
  struct Pending {
    std::int64_t due_us = 0;
    hrp::handrail_estimate_t e{};
  } pending;
  bool have_pending = false;

  explicit Rig(std::uint64_t seed, double gp_bias_m = 0.05, double gp_bias_deg = 2.0,
               bool gp_while_handrail_holds = false)
      : sensors(hub, fsw_app::hil_sensor_params(gp_bias_m, gp_bias_deg), seed),
        cfg(make_cfg(gp_while_handrail_holds)),
        task(hub, cfg, clock),
        flyer(start_pose(), sim_hal::FlyerParams{}, seed),
        rng(seed * 31 + 7) {
    hub.subscribe(fsw_app::channel::kRobotPose, &pose_box);
  }
  static fsw_app::LocalizationTaskConfig make_cfg(bool gp_while_handrail_holds) {
    fsw_app::LocalizationTaskConfig c;
    c.gp_while_handrail_holds = gp_while_handrail_holds;
    c.filter.T_body_cam = loc::default_T_body_cam();
    return c;
  }
  double gauss() { return rng.normal(); }

  // The estimator's message for a frame captured now: the true relative
  // pose with a little detection noise, BE when both ends are in view.
  hrp::handrail_estimate_t detect() {
    hrp::handrail_estimate_t e{};
    e.capture_utime = clock.t_us;
    e.frame_id = ++frame_id;
    const Eigen::Isometry3d T_world_cam = flyer.pose() * cfg.filter.T_body_cam;
    Eigen::Isometry3d T_cam_handrail = T_world_cam.inverse() * world_handrail();
    Eigen::Isometry3d noise = Eigen::Isometry3d::Identity();
    noise.translation() = 0.0015 * Eigen::Vector3d(gauss(), gauss(), gauss());
    const Eigen::Vector3d phi = 0.003 * Eigen::Vector3d(gauss(), gauss(), gauss());
    noise.linear() = Eigen::AngleAxisd(phi.norm(), phi.normalized()).toRotationMatrix();
    Eigen::Isometry3d shift = Eigen::Isometry3d::Identity();
    shift.translation() = handrail_offset_cam;
    T_cam_handrail = shift * T_cam_handrail * noise;
    e.state = hrp::handrail_estimate_t::STATE_BE;
    e.num_ends = 2;
    e.bar_length_m = bar_length_m;
    if (one_end) {
      const Eigen::Vector3d top_end = T_cam_handrail * Eigen::Vector3d(0, 0, 0.5 * bar_length_m);
      T_cam_handrail.translation() =
          T_cam_handrail * Eigen::Vector3d(0, 0, 0.5 * bar_length_m - 0.15);
      e.state = hrp::handrail_estimate_t::STATE_OE;
      e.num_ends = 1;
      e.bar_length_m = 0.0;
      for (int k = 0; k < 3; ++k) e.ends_cam_m[0][k] = top_end[k];
    }
    fsw_app::to_msg(T_cam_handrail, &e.T_cam_handrail);
    fsw_app::to_msg(cfg.filter.T_body_cam * T_cam_handrail, &e.T_body_handrail);
    fsw_app::to_msg(Eigen::Isometry3d::Identity(), &e.T_body_target);
    return e;
  }

  // 10 ms ticks for `seconds`: the flyer on a slow weave, the sensors, the
  // handrail estimates at 5 Hz 100 ms late, the task at 100 Hz.
  void run(double seconds) {
    const int ticks = static_cast<int>(seconds * 100);
    for (int k = 0; k < ticks; ++k) {
      clock.t_us += 10000;
      const double t = 1e-6 * static_cast<double>(clock.t_us);
      const Eigen::Vector3d v_cmd(0.02 * std::sin(0.3 * t), 0.04 * std::sin(0.21 * t), 0.0);
      const Eigen::Vector3d w_cmd(0.0, 0.0, 0.03 * std::sin(0.17 * t));
      flyer.step(0.01, v_cmd, w_cmd);
      sensors.on_tick(clock.t_us, flyer.pose(), flyer.velocity(), flyer.angular_velocity(),
                      k % 2 == 0);
      if (handrail_on && clock.t_us >= next_frame_us) {
        next_frame_us = clock.t_us + 200000;
        pending.due_us = clock.t_us + 100000;
        pending.e = detect();
        have_pending = true;
      }
      if (have_pending && clock.t_us >= pending.due_us) {
        pending.e.utime = clock.t_us;
        estimate_pub.publish(pending.e);
        have_pending = false;
      }
      while (hub.handle(0) > 0) {
      }
      task.step();
      while (hub.handle(0) > 0) {
      }
    }
  }
  Eigen::Isometry3d estimate() const { return fsw_app::from_msg(task.last_pose().T_world_body); }
  double error_m() const { return (estimate().translation() - flyer.pose().translation()).norm(); }
  // The body's pose relative to the handrail, as the filter has it (its
  // map) and as it is: what perching needs.
  double relative_error_m() const {
    const loc::HandrailMap& map = task.filter().handrail_map();
    const Eigen::Isometry3d est = map.T_world_handrail.inverse() * estimate();
    const Eigen::Isometry3d truth = world_handrail().inverse() * flyer.pose();
    return (est.translation() - truth.translation()).norm();
  }
  double position_sigma_m() const {
    double v = 0.0;
    for (int k = 0; k < 3; ++k) v = std::max(v, task.last_pose().pose_covariance[k][k]);
    return std::sqrt(v);
  }
  // Relative to the handrail map, largest axis (what the handrail updates
  // know; the world sigma holds the map's own uncertainty too).
  double relative_sigma_m() const {
    return std::sqrt(task.filter().estimate().handrail_position_cov.diagonal().maxCoeff());
  }
};

void test_follows_the_gp_without_the_handrail(void**) {
  Rig r(3);
  r.handrail_on = false;
  r.run(60.0);
  const fsw_app::LocalizationTaskCounters c = r.task.counters();
  std::printf("IMU in %llu, GP in %llu, poses %llu, error %.1f mm, sigma %.1f mm\n",
              static_cast<unsigned long long>(c.imu_in), static_cast<unsigned long long>(c.gp_in),
              static_cast<unsigned long long>(c.poses_published), 1e3 * r.error_m(),
              1e3 * r.position_sigma_m());
  assert_true(r.task.filter().initialized());
  assert_true(c.poses_published > 3000);
  assert_int_equal(r.task.last_pose().source, hrp::robot_pose_t::SOURCE_FILTER);
  // GP 5 cm off: the filter is about as good as it, never diverging.
  assert_true(r.error_m() < 0.09);
}

void test_handrail_pins_the_pose_relative_to_the_bar(void**) {
  Rig r(4);
  double worst = 0.0;
  r.run(10.0);
  for (int k = 0; k < 40; ++k) {
    r.run(0.5);
    worst = std::max(worst, r.relative_error_m());
  }
  const loc::FilterCounters& c = r.task.filter().counters();
  std::printf("relative error now %.1f mm, worst %.1f mm; world %.1f mm; handrail accepted %u\n",
              1e3 * r.relative_error_m(), 1e3 * worst, 1e3 * r.error_m(),
              c.count(loc::MeasurementKind::kHandrailEnds, loc::UpdateStatus::kAccepted));
  assert_true(r.task.filter().handrail_map().valid);
  assert_true(worst < 0.01);
}

std::uint32_t count(const Rig& r, loc::MeasurementKind k, loc::UpdateStatus s) {
  return r.task.filter().counters().count(k, s);
}

// A 0.76 m bar (the application's configured length is 0.55 m): BE
// estimates for 10 s teach the task its length, then only the top end is
// in view. Each OE centre is placed half the learned length from that end,
// so the estimates agree with the BE ones: none is gated and the pose stays
// on the bar. (Placed with 0.55 m they would be 10.5 cm off along it: in a
// HIL perch on approach-iss-mesh, 1.5 cm off between BE and OE frames made
// the filter's accelerometer bias take the difference, the BE frames were
// gated after, and the estimate ran 0.5 m along the bar.)
void test_one_end_of_a_longer_bar_keeps_the_pose(void**) {
  Rig r(8);
  r.bar_length_m = 0.76;
  r.run(10.0);
  r.one_end = true;
  double worst = 0.0;
  for (int k = 0; k < 30; ++k) {
    r.run(0.5);
    worst = std::max(worst, r.relative_error_m());
  }
  const fsw_app::LocalizerReport rep = fsw_app::localizer_report(r.task);
  std::printf(
      "0.76 m bar, top end only for 15 s: relative error worst %.1f mm; accepted %u, "
      "gated %u\n",
      1e3 * worst, rep.handrail_accepted, rep.handrail_rejected_gate);
  assert_int_equal(rep.handrail_rejected_gate, 0);
  assert_true(rep.handrail_no_end_accepted == 0);
  assert_true(worst < 0.01);
}

// Only the top end in view from the start: no length is known, so the OE
// estimates are used as NE (the along-bar position is not claimed). They
// build a line map (its origin somewhere on the bar), and from then on they
// are NE updates: across the bar the handrail holds the pose from the
// first frames.
void test_one_end_with_no_length_known_is_used_as_no_end(void**) {
  Rig r(9);
  r.bar_length_m = 0.76;
  r.one_end = true;
  r.run(8.0);
  const fsw_app::LocalizerReport rep = fsw_app::localizer_report(r.task);
  std::printf("top end only from the start: %u with an end, %u as NE, map %s, %u sightings\n",
              rep.handrail_accepted, rep.handrail_no_end_accepted,
              rep.map_valid ? "valid" : "not built", rep.handrail_map_sightings);
  assert_true(rep.map_valid);
  assert_false(r.task.filter().handrail_map().along_known);
  assert_true(rep.handrail_no_end_accepted > 20);
  assert_int_equal(rep.handrail_accepted, 0);
}

// The handrail lost mid-approach: the filter goes on with the GP, its
// covariance relative to the handrail grows, no handrail holds the pose,
// and it stays within the GP's error of the truth.
void test_handrail_lost_falls_back_on_the_gp(void**) {
  Rig r(5);
  r.run(15.0);
  assert_true(r.task.last_pose().handrail_holding);
  const double sigma_with = r.relative_sigma_m();
  const std::uint32_t gp_before =
      count(r, loc::MeasurementKind::kGpPose, loc::UpdateStatus::kAccepted);
  r.handrail_on = false;
  r.run(12.0);
  std::printf(
      "position sigma relative to the handrail %.1f mm with it, %.1f mm 12 s after losing it "
      "(world %.1f mm)\n",
      1e3 * sigma_with, 1e3 * r.relative_sigma_m(), 1e3 * r.position_sigma_m());
  assert_false(r.task.last_pose().handrail_holding);
  assert_true(r.relative_sigma_m() > 1.5 * sigma_with);
  assert_true(count(r, loc::MeasurementKind::kGpPose, loc::UpdateStatus::kAccepted) >
              gp_before + 10);
  // Every one of those is the fall-back, counted by the task, and the sigma
  // while the handrail held is the one the run summary reports.
  const fsw_app::LocalizationTaskCounters c = r.task.counters();
  assert_true(c.gp_fallback_accepted + gp_before >=
              count(r, loc::MeasurementKind::kGpPose, loc::UpdateStatus::kAccepted));
  assert_true(c.across_bar_sigma_held_min_m > 0.0 && c.across_bar_sigma_held_min_m < sigma_with &&
              c.across_bar_sigma_m > 1.5 * c.across_bar_sigma_held_min_m);
  // In the world the handrail knows no better than the map it was placed
  // with (the GP's pose then): the world sigma while it held stays several
  // times what it knows across the bar, and does not jump when it is lost.
  assert_true(c.position_sigma_held_min_m > 3.0 * c.across_bar_sigma_held_min_m);
  assert_true(c.position_sigma_m < 2.0 * c.position_sigma_held_min_m);
  assert_true(r.error_m() < 0.09);
}

// Given the handrail's surveyed world pose (here its true one, 2 mm and
// 0.1 deg of survey sigma), the handrail places the robot in the world: the
// world error drops from the GP's 5 cm to what the detections give.
void test_surveyed_handrail_gives_the_world_pose(void**) {
  Rig r(4);
  loc::HandrailMap survey;
  survey.T_world_handrail = world_handrail();
  survey.position_sigma_m = 0.002;
  survey.attitude_sigma_rad = 0.1 * 3.14159265358979 / 180.0;
  assert_int_equal(static_cast<int>(r.task.set_handrail_survey(survey)),
                   static_cast<int>(loc::UpdateStatus::kAccepted));
  double worst = 0.0;
  r.run(10.0);
  for (int k = 0; k < 40; ++k) {
    r.run(0.5);
    worst = std::max(worst, r.error_m());
  }
  std::printf("surveyed handrail: world error now %.1f mm, worst %.1f mm over 20 s\n",
              1e3 * r.error_m(), 1e3 * worst);
  assert_true(r.task.filter().handrail_map().surveyed);
  assert_true(worst < 0.01);
}

// No IMU sample for 0.5 s: a gap bridged by the filter's rule (not lost),
// counted by the task from the IMU's counter; the pose relative to the bar
// stays within 1 cm.
void test_imu_silent_half_a_second_is_bridged(void**) {
  Rig r(6);
  r.run(12.0);
  r.sensors.silence_imu_until(r.clock.t_us + 500000);
  r.run(3.0);
  const loc::FilterCounters& c = r.task.filter().counters();
  std::printf("gaps bridged %u, lost %u, IMU samples missing %llu, relative error %.1f mm\n",
              c.count(loc::ImuStatus::kGapBridged), c.count(loc::ImuStatus::kGapLost),
              static_cast<unsigned long long>(r.task.counters().imu_seq_gaps),
              1e3 * r.relative_error_m());
  assert_int_equal(c.count(loc::ImuStatus::kGapBridged), 1);
  assert_int_equal(c.count(loc::ImuStatus::kGapLost), 0);
  assert_true(r.task.counters().imu_seq_gaps >= 28);  // 0.5 s at 62.5 Hz, less the edges
  assert_false(r.task.last_pose().lost);
  assert_true(r.relative_error_m() < 0.01);
}

// Handrail estimates 5 cm off for 1.6 s: every one rejected by the gate and
// counted, the pose unmoved (ten in a row would drop the map, the filter's
// rule for a handrail that moved); good ones are taken again after.
void test_handrail_5cm_off_is_gated(void**) {
  Rig r(7);
  r.run(12.0);
  const std::uint32_t gated_before =
      count(r, loc::MeasurementKind::kHandrailEnds, loc::UpdateStatus::kRejectedGate);
  const std::uint32_t accepted_before =
      count(r, loc::MeasurementKind::kHandrailEnds, loc::UpdateStatus::kAccepted);
  r.handrail_offset_cam = Eigen::Vector3d(0.05, 0.0, 0.0);
  r.run(1.6);
  const std::uint32_t gated =
      count(r, loc::MeasurementKind::kHandrailEnds, loc::UpdateStatus::kRejectedGate) -
      gated_before;
  std::printf("gated %u of 8 off estimates; relative error %.1f mm\n", gated,
              1e3 * r.relative_error_m());
  assert_true(gated >= 7);
  assert_true(r.task.filter().handrail_map().valid);
  assert_int_equal(count(r, loc::MeasurementKind::kHandrailEnds, loc::UpdateStatus::kAccepted),
                   accepted_before);
  assert_true(r.relative_error_m() < 0.01);
  r.handrail_offset_cam.setZero();
  r.run(2.0);
  assert_true(count(r, loc::MeasurementKind::kHandrailEnds, loc::UpdateStatus::kAccepted) >
              accepted_before);
}

// The GP jumping 20 cm: while the handrail holds the pose no GP pose is
// applied (the task's rule: the handrail map is the reference when
// perching), so the jump changes nothing; applied anyway (the option off),
// the filter's gate rejects every jumped pose; without the handrail, three
// agreeing poses relocalise the filter onto them. Never a divergence.
void test_gp_jump_rejected_while_the_handrail_holds_taken_without(void**) {
  Rig held(8);
  held.run(12.0);
  const std::uint64_t held_before = held.task.counters().gp_held_off;
  held.sensors.jump_gp(Eigen::Vector3d(0.0, 0.2, 0.0));
  held.run(6.0);
  std::printf("handrail holding: %llu GP poses held off, relative %.1f mm\n",
              static_cast<unsigned long long>(held.task.counters().gp_held_off - held_before),
              1e3 * held.relative_error_m());
  assert_true(held.task.counters().gp_held_off >= held_before + 6);
  assert_int_equal(count(held, loc::MeasurementKind::kGpPose, loc::UpdateStatus::kRelocalized), 0);
  assert_true(held.relative_error_m() < 0.01);

  Rig r(8, 0.05, 2.0, true);
  r.run(12.0);
  r.sensors.jump_gp(Eigen::Vector3d(0.0, 0.2, 0.0));
  r.run(6.0);
  const std::uint32_t rejected =
      count(r, loc::MeasurementKind::kGpPose, loc::UpdateStatus::kRejectedGate) +
      count(r, loc::MeasurementKind::kGpPose, loc::UpdateStatus::kRejectedJump);
  std::printf("GP applied while holding: %u rejected, %u relocalisations, relative %.1f mm\n",
              rejected, count(r, loc::MeasurementKind::kGpPose, loc::UpdateStatus::kRelocalized),
              1e3 * r.relative_error_m());
  assert_true(rejected >= 5);
  assert_int_equal(count(r, loc::MeasurementKind::kGpPose, loc::UpdateStatus::kRelocalized), 0);
  assert_true(r.relative_error_m() < 0.01);

  Rig g(9);
  g.handrail_on = false;
  g.run(12.0);
  g.sensors.jump_gp(Eigen::Vector3d(0.0, 0.2, 0.0));
  g.run(6.0);
  std::printf("no handrail: %u relocalisations, world error %.1f mm\n",
              count(g, loc::MeasurementKind::kGpPose, loc::UpdateStatus::kRelocalized),
              1e3 * g.error_m());
  assert_int_equal(count(g, loc::MeasurementKind::kGpPose, loc::UpdateStatus::kRelocalized), 1);
  // Now with the jumped GP: 20 cm off the truth, as the GP is.
  assert_near(g.error_m(), 0.2, 0.09);
}

// NaN in any input: refused by the hub's check (counted NOT_FINITE on its
// channel), so the filter never sees it and its counts do not move.
void test_nan_inputs_rejected_and_counted(void**) {
  Rig r(10);
  r.run(8.0);
  const loc::FilterCounters before = r.task.filter().counters();
  const double nan = std::nan("");
  fsw_app::Publisher<hrp::imu_sample_t> imu(r.hub, fsw_app::channel::kImuSample);
  fsw_app::Publisher<hrp::gp_pose_t> gp(r.hub, fsw_app::channel::kGpPose);
  hrp::imu_sample_t s{};
  s.utime = r.clock.t_us + 1;
  s.seq = 1 << 20;
  s.omega_body_radps[1] = nan;
  imu.publish(s);
  hrp::gp_pose_t g{};
  g.utime = g.capture_utime = r.clock.t_us;
  fsw_app::to_msg(r.flyer.pose(), &g.T_world_body);
  g.covariance[2][2] = nan;
  gp.publish(g);
  hrp::handrail_estimate_t e = r.detect();
  e.T_cam_handrail.position_m[0] = nan;
  r.estimate_pub.publish(e);
  while (r.hub.handle(0) > 0) {
  }
  r.task.step();
  const loc::FilterCounters& after = r.task.filter().counters();
  std::size_t n = 0;
  const fsw_app::ChannelInput* in = r.hub.inputs(&n);
  std::uint64_t not_finite = 0;
  for (std::size_t k = 0; k < n; ++k) {
    not_finite += in[k].counts->rejected[static_cast<int>(fsw_app::InputReject::kNotFinite)];
  }
  assert_int_equal(not_finite, 3);
  for (int k = 0; k < loc::kNumMeasurementKinds; ++k) {
    for (int st = 0; st < loc::kNumUpdateStatus; ++st) {
      assert_int_equal(after.updates[k][st], before.updates[k][st]);
    }
  }
  assert_true(std::isfinite(r.estimate().translation().x()));
}

// The robot's tasks subscribe to ROBOT_POSE, never to the truth: the channel
// lists of a hub with the localization, estimator and perch-manager tasks.
void test_no_robot_task_subscribes_to_the_truth(void**) {
  SimClock clock;
  fsw_app::LcmHub hub("memq://", clock);
  fsw_app::LocalizationTask localizer(hub, fsw_app::LocalizationTaskConfig{}, clock);
  fsw_app::FrameRing ring(3, 224, 171);
  fsw_app::CameraTask camera(ring, 224, 171);
  fsw_app::EstimatorTask estimator(hub, camera, ring, fsw_app::EstimatorTaskConfig{}, clock);
  fsw_app::PerchManager manager(hub, fsw_app::ApproachConfig{}, Eigen::Vector3d(0.4, 0, 0), clock,
                                20.0);
  std::size_t n = 0;
  const fsw_app::ChannelInput* in = hub.inputs(&n);
  bool robot_pose = false;
  for (std::size_t k = 0; k < n; ++k) {
    std::printf("  subscribed: %s\n", in[k].channel);
    assert_true(std::strcmp(in[k].channel, fsw_app::channel::kTruthPose) != 0);
    robot_pose = robot_pose || std::strcmp(in[k].channel, fsw_app::channel::kRobotPose) == 0;
  }
  assert_true(robot_pose);
  assert_true(n >= 5);  // one entry per channel
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_follows_the_gp_without_the_handrail),
      cmocka_unit_test(test_handrail_pins_the_pose_relative_to_the_bar),
      cmocka_unit_test(test_one_end_of_a_longer_bar_keeps_the_pose),
      cmocka_unit_test(test_one_end_with_no_length_known_is_used_as_no_end),
      cmocka_unit_test(test_handrail_lost_falls_back_on_the_gp),
      cmocka_unit_test(test_surveyed_handrail_gives_the_world_pose),
      cmocka_unit_test(test_imu_silent_half_a_second_is_bridged),
      cmocka_unit_test(test_handrail_5cm_off_is_gated),
      cmocka_unit_test(test_gp_jump_rejected_while_the_handrail_holds_taken_without),
      cmocka_unit_test(test_nan_inputs_rejected_and_counted),
      cmocka_unit_test(test_no_robot_task_subscribes_to_the_truth),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
