// dynamic_test: the paper's dynamic experiment (its Figure 17) in the
// simulator. The robot moves in a plane (out from the wall, along it, and
// in yaw, as on the paper's granite table) in front of a handrail on a wall,
// the camera 0.5 to 1 m from it, for a minute; the simulated ToF camera
// renders every frame from the true pose, the real detector finds the
// handrail, and fsw_app's localization task fuses it with the simulated IMU
// and general-purpose localizer, all in lock step on simulated time over
// LCM (memq://). Writes DIR/summary.json and DIR/dynamic-test.png.
//
// By default the filter is given the handrail's surveyed world pose (as the
// paper's table test had its handrail at a known place, and as the station's
// handrails sit at known rack positions): the true pose off by a seeded
// survey error of --survey-sigma. The handrail then places the robot in the
// world, and the error scored is the world-frame one, the filter's body
// position against the true one, in the wall's axes (x out from the wall,
// y along it, horizontal). Beside it, the error relative to the handrail,
// what perching needs: the body in the filter's map against the body in the
// true handrail frame. With --no-survey the map comes from the first
// confident sightings (what a perch does today); the world error then
// carries the GP's error at the time the map was built (centimetres), and
// only the relative error is as good as the handrail.
#include <sys/stat.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "dynamic_chart.hpp"
#include "estimator/config.hpp"
#include "estimator/localization/handrail_map.hpp"
#include "fsw_app/app_config.hpp"
#include "fsw_app/camera_task.hpp"
#include "fsw_app/estimator_task.hpp"
#include "fsw_app/frame_ring.hpp"
#include "fsw_app/localization_task.hpp"
#include "fsw_app/msg_convert.hpp"
#include "hal/clock.hpp"
#include "hil_sensors.hpp"
#include "output_dir.hpp"
#include "sim_hal/scenario.hpp"
#include "sim_hal/simulated_camera.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Options {
  std::string out = "dynamic-test-out";
  std::string scenario = "sim_hal/scenarios/approach-iss.json";
  std::string config = "fsw_app/config/fsw_app.json";
  std::uint64_t seed = 1;
  double duration_s = 60.0;
  double gp_bias_m = 0.03, gp_bias_deg = 1.0;
  bool survey = true;
  std::string handrail;  // iss or round; empty: the scenario's handrail's kind
  double survey_sigma_m = 0.002, survey_sigma_deg = 0.1;
};

void usage(std::FILE* f) {
  std::fprintf(f,
               "usage: dynamic_test [--out DIR] [--scenario FILE] [--config FILE] [--seed N]\n"
               "                    [--duration S] [--gp-error M,DEG]\n"
               "                    [--survey-sigma M,DEG | --no-survey] [--handrail iss|round]\n"
               "The paper's dynamic experiment (Figure 17) in the simulator: planar motion in\n"
               "front of a handrail for a minute, the localization filter against the truth.\n"
               "Writes DIR/summary.json (mean and sd of the absolute error in x and y, world\n"
               "frame, and relative to the handrail) and DIR/dynamic-test.png. The handrail's\n"
               "world pose is surveyed (off by a seeded error of --survey-sigma, default\n"
               "0.002 m and 0.1 deg per axis); --no-survey: the map from its first sightings.\n"
               "--handrail: the geometry the detector looks for (default: the scenario's first\n"
               "handrail's, round for the paper's round bar, iss otherwise; its length always).\n"
               "Defaults: dynamic-test-out, approach-iss, 60 s, GP 0.03 m and 1 deg off.\n");
}

// The wall's axes at the target bar: n out of the wall, a along it
// (horizontal), up; the bar's centre c.
struct WallFrame {
  Eigen::Vector3d n, a, up, c;
};

// The camera on the path at t: out from the wall 0.5 to 1.0 m, along it
// +-12 cm, yaw +-6 deg, smooth sines of incommensurate periods.
Eigen::Isometry3d camera_on_path(const WallFrame& w, double t) {
  const double out = 0.75 + 0.22 * std::sin(2 * kPi * t / 37.0 - 0.5 * kPi);
  const double along = 0.12 * std::sin(2 * kPi * t / 23.0 + 0.5);
  const double yaw = 6.0 * kPi / 180.0 * std::sin(2 * kPi * t / 29.0 + 1.0);
  Eigen::Matrix3d R0;
  const Eigen::Vector3d forward = -w.n;
  R0.col(0) = forward.cross(w.up);  // right
  R0.col(1) = -w.up;                // down
  R0.col(2) = forward;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, w.up).toRotationMatrix() * R0;
  T.translation() = w.c + out * w.n + along * w.a;
  return T;
}

class PathSource final : public sim_hal::CameraPoseSource {
 public:
  PathSource(const WallFrame& w, const Eigen::Isometry3d& T_body_cam) : w_(w), T_bc_(T_body_cam) {}
  Eigen::Isometry3d T_world_body(double t) const { return camera_on_path(w_, t) * T_bc_.inverse(); }
  Eigen::Isometry3d T_world_cam(std::int64_t now_us) override {
    return camera_on_path(w_, 1e-6 * static_cast<double>(now_us));
  }

 private:
  WallFrame w_;
  Eigen::Isometry3d T_bc_;
};

struct AbsStats {
  double n = 0, sum = 0, sum2 = 0, signed_sum = 0;
  void add(double e) {
    n += 1;
    signed_sum += e;
    sum += std::fabs(e);
    sum2 += e * e;
  }
  double mean() const { return n > 0 ? sum / n : -1.0; }
  double bias() const { return n > 0 ? signed_sum / n : 0.0; }  // the signed mean
  double sd() const { return n > 1 ? std::sqrt(std::max(0.0, sum2 / n - mean() * mean())) : -1.0; }
};

bool parse(int argc, char** argv, Options* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      usage(stdout);
      std::exit(0);
    }
    if (a == "--no-survey") {
      o->survey = false;
      continue;
    }
    if (i + 1 >= argc) return false;
    const std::string v = argv[++i];
    if (a == "--out") {
      o->out = v;
    } else if (a == "--scenario") {
      o->scenario = v;
    } else if (a == "--config") {
      o->config = v;
    } else if (a == "--seed") {
      o->seed = std::strtoull(v.c_str(), nullptr, 10);
    } else if (a == "--duration") {
      o->duration_s = std::strtod(v.c_str(), nullptr);
      if (!(o->duration_s >= 10.0 && o->duration_s <= 600.0)) return false;
    } else if (a == "--gp-error") {
      if (std::sscanf(v.c_str(), "%lf,%lf", &o->gp_bias_m, &o->gp_bias_deg) != 2) return false;
    } else if (a == "--handrail") {
      if (v != "iss" && v != "round") return false;
      o->handrail = v;
    } else if (a == "--survey-sigma") {
      if (std::sscanf(v.c_str(), "%lf,%lf", &o->survey_sigma_m, &o->survey_sigma_deg) != 2 ||
          !(o->survey_sigma_m >= 0.0 && o->survey_sigma_m <= 0.1) ||
          !(o->survey_sigma_deg >= 0.0 && o->survey_sigma_deg <= 5.0)) {
        return false;
      }
    } else {
      return false;
    }
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  if (!parse(argc, argv, &opt)) {
    usage(stderr);
    return 2;
  }
  std::string error;
  fsw_app::AppConfig cfg;
  sim_hal::Scenario scenario;
  if (!fsw_app::load_app_config(opt.config, &cfg, &error) ||
      !sim_hal::load_scenario(opt.scenario, &scenario, &error)) {
    std::fprintf(stderr, "dynamic_test: %s\n", error.c_str());
    return 2;
  }
  if (scenario.scene.handrails.empty()) {
    std::fprintf(stderr, "dynamic_test: %s has no handrail\n", opt.scenario.c_str());
    return 2;
  }
  if (!tools::make_output_dir(opt.out, &error)) {
    std::fprintf(stderr, "dynamic_test: --out: %s\n", error.c_str());
    return 2;
  }
  const sim_hal::Handrail& h = scenario.scene.handrails.front();
  WallFrame w;
  w.n = h.normal.normalized();
  w.up = (Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitZ().dot(w.n) * w.n).normalized();
  w.a = w.up.cross(w.n);
  w.c = 0.5 * (h.end_point(0) + h.end_point(1));
  // The true handrail frame as the filter's map has it (x = wall normal,
  // z = along the bar); its axis sign is matched to the map's below.
  Eigen::Isometry3d T_world_handrail = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d axis = (h.end_point(1) - h.end_point(0)).normalized();
  T_world_handrail.linear().col(0) = w.n;
  T_world_handrail.linear().col(1) = axis.cross(w.n);
  T_world_handrail.linear().col(2) = axis;
  T_world_handrail.translation() = w.c;
  // The survey: the true pose off by a draw of its sigma on each axis.
  estimator::localization::HandrailMap survey;
  survey.T_world_handrail = T_world_handrail;
  survey.position_sigma_m = opt.survey_sigma_m;
  survey.attitude_sigma_rad = opt.survey_sigma_deg * kPi / 180.0;
  Eigen::Vector3d survey_dp = Eigen::Vector3d::Zero(), survey_dtheta = Eigen::Vector3d::Zero();
  if (opt.survey) {
    std::mt19937_64 rng(opt.seed ^ 0x5eed5eedULL);
    std::normal_distribution<double> unit(0.0, 1.0);
    for (int k = 0; k < 3; ++k) survey_dp[k] = survey.position_sigma_m * unit(rng);
    for (int k = 0; k < 3; ++k) survey_dtheta[k] = survey.attitude_sigma_rad * unit(rng);
    survey.T_world_handrail.translation() += survey_dp;
    if (survey_dtheta.norm() > 0.0) {
      survey.T_world_handrail.linear() =
          Eigen::AngleAxisd(survey_dtheta.norm(), survey_dtheta.normalized()).toRotationMatrix() *
          T_world_handrail.linear();
    }
  }

  hal::ManualClock clock(1000000);  // simulated time starts at 1 s
  fsw_app::LcmHub hub("memq://", clock);
  PathSource path(w, cfg.T_body_cam);
  fsw_app::HilSensors sensors(hub, fsw_app::hil_sensor_params(opt.gp_bias_m, opt.gp_bias_deg),
                              opt.seed);
  fsw_app::LocalizationTask localizer(hub, fsw_app::localization_task_config(cfg), clock);
  if (opt.survey &&
      localizer.set_handrail_survey(survey) != estimator::localization::UpdateStatus::kAccepted) {
    std::fprintf(stderr, "dynamic_test: the filter refused the survey of %s's handrail\n",
                 opt.scenario.c_str());
    return 1;
  }
  sim_hal::SimulatedCamera camera(scenario, clock, sim_hal::SimulatedCamera::Pacing::kRealTime);
  camera.set_pose_source(&path);
  std::uint32_t max_w = 0, max_h = 0;
  if (camera.initialize() != hal::CameraStatus::kSuccess ||
      camera.set_use_case(cfg.use_case.c_str()) != hal::CameraStatus::kSuccess ||
      camera.max_frame_size(&max_w, &max_h) != hal::CameraStatus::kSuccess) {
    std::fprintf(stderr, "dynamic_test: the simulated camera would not start\n");
    return 1;
  }
  fsw_app::FrameRing ring(3, max_w, max_h);
  fsw_app::CameraTask camera_task(ring, max_w, max_h);
  (void)camera.register_data_listener(&camera_task);
  fsw_app::EstimatorTaskConfig est_cfg;
  est_cfg.detector = cfg.estimator;
  // The detector looks for the bar in view: the ISS geometry on a round
  // bar finds no end (its front and cross-section are another bar's).
  const bool round =
      opt.handrail.empty() ? h.kind == sim_hal::HandrailKind::kPaperRound : opt.handrail == "round";
  const auto length_m = static_cast<float>(h.bar_length_m);
  est_cfg.detector.handrail =
      round ? estimator::paper_round_handrail(length_m) : estimator::iss_handrail(length_m);
  est_cfg.detector.budget_us = 0;  // simulated time: no budget to keep
  est_cfg.T_body_cam = cfg.T_body_cam;
  est_cfg.arm = cfg.perch.geometry;
  est_cfg.max_width = max_w;
  est_cfg.max_height = max_h;
  fsw_app::EstimatorTask estimator(hub, camera_task, ring, est_cfg, clock);
  fsw_app::Mailbox<hrp::gp_pose_t> gp_box;
  hub.subscribe(fsw_app::channel::kGpPose, &gp_box);

  // 10 ms ticks: the sensors every tick, a frame every 200 ms whose estimate
  // is published 60 ms later (the detector's time on the robot), the
  // localizer every tick, a sample of the track every 50 ms after 5 s of
  // settling (the map needs its first sightings).
  const double settle_s = 5.0;
  const auto ticks = static_cast<int>((opt.duration_s + settle_s) * 100);
  std::vector<tools::TrackSample> track;
  std::vector<tools::FixSample> fixes;
  AbsStats rel_x, rel_y, world_x, world_y, gp_x, gp_y;
  std::int64_t next_frame_us = clock.now_us(), estimate_due_us = -1;
  std::uint64_t gp_seen = 0;
  hrp::gp_pose_t gp_msg{};
  Eigen::Isometry3d T_prev = path.T_world_body(1e-6 * static_cast<double>(clock.now_us()));
  const auto drain = [&hub] {
    while (hub.handle(0) > 0) {
    }
  };
  const auto in_wall = [&w](const Eigen::Vector3d& p) {
    return Eigen::Vector2d((p - w.c).dot(w.n), (p - w.c).dot(w.a));
  };
  for (int k = 0; k < ticks; ++k) {
    clock.advance_us(10000);
    const std::int64_t now = clock.now_us();
    const double t = 1e-6 * static_cast<double>(now);
    const Eigen::Isometry3d T_true = path.T_world_body(t);
    const Eigen::Vector3d v = (T_true.translation() - T_prev.translation()) / 0.01;
    T_prev = T_true;
    sensors.on_tick(now, T_true, v, Eigen::Vector3d::Zero(), k % 2 == 0);
    if (now >= next_frame_us) {
      next_frame_us += 200000;
      if (camera.capture_next() == hal::CameraStatus::kSuccess) estimate_due_us = now + 60000;
    }
    if (estimate_due_us >= 0 && now >= estimate_due_us) {
      estimate_due_us = -1;
      estimator.process_next(0);
    }
    drain();
    localizer.step();
    drain();
    const double t_run = t - 1.0 - settle_s;
    if (const std::uint64_t seq = gp_box.read(&gp_msg); seq != gp_seen) {
      gp_seen = seq;
      const Eigen::Vector2d g = in_wall(fsw_app::from_msg(gp_msg.T_world_body).translation());
      const Eigen::Vector2d tr = in_wall(
          path.T_world_body(1e-6 * static_cast<double>(gp_msg.capture_utime)).translation());
      if (t_run >= 0.0) {
        fixes.push_back(
            {1e-6 * static_cast<double>(gp_msg.capture_utime) - 1.0 - settle_s, g.x(), g.y()});
        gp_x.add(g.x() - tr.x());
        gp_y.add(g.y() - tr.y());
      }
    }
    if (t_run < 0.0 || k % 5 != 0 || !localizer.filter().initialized()) continue;
    const estimator::localization::HandrailMap map = localizer.filter().handrail_map();
    const Eigen::Isometry3d T_est = fsw_app::from_msg(localizer.last_pose().T_world_body);
    const Eigen::Isometry3d T_true_at =
        path.T_world_body(1e-6 * static_cast<double>(localizer.last_pose().utime));
    const Eigen::Vector2d tr = in_wall(T_true_at.translation());
    const Eigen::Vector2d world = in_wall(T_est.translation());
    world_x.add(world.x() - tr.x());
    world_y.add(world.y() - tr.y());
    Eigen::Vector2d rel = world;
    if (map.valid) {
      // The filter's pose in its map, put into the true handrail frame
      // (with the map's axis sign).
      Eigen::Isometry3d T_wh = T_world_handrail;
      if (map.T_world_handrail.linear().col(2).dot(axis) < 0.0) {
        T_wh.linear() = estimator::localization::flip_axis(T_wh.linear());
      }
      rel = in_wall((T_wh * map.T_world_handrail.inverse() * T_est).translation());
      rel_x.add(rel.x() - tr.x());
      rel_y.add(rel.y() - tr.y());
    }
    track.push_back({t_run, tr.x(), tr.y(), world.x(), world.y()});
  }
  const fsw_app::LocalizerReport r = fsw_app::localizer_report(localizer);
  const std::string png = opt.out + "/dynamic-test.png";
  char title[160];
  std::snprintf(
      title, sizeof title, "FIG. 17, WORLD FRAME: MEAN ABS ERROR X %.1f MM, Y %.1f MM, HANDRAIL %s",
      1e3 * world_x.mean(), 1e3 * world_y.mean(), opt.survey ? "SURVEYED" : "NOT SURVEYED");
  if (!tools::write_track_chart(png, title, track, fixes, &error)) {
    std::fprintf(stderr, "dynamic_test: %s: %s\n", png.c_str(), error.c_str());
    return 1;
  }
  const std::string json = opt.out + "/summary.json";
  std::FILE* f = std::fopen(json.c_str(), "w");
  if (!f) {
    std::fprintf(stderr, "dynamic_test: cannot write %s\n", json.c_str());
    return 1;
  }
  const bool met = world_x.mean() >= 0.0 && world_x.mean() <= 0.005 && world_y.mean() >= 0.0 &&
                   world_y.mean() <= 0.005;
  std::fprintf(f,
               "{\"scenario\": \"%s\", \"handrail\": \"%s\", \"seed\": %llu, \"duration_s\": %.1f, "
               "\"samples\": %.0f,\n"
               " \"frame\": \"world: the body's position against the true one, wall axes: x out, y "
               "along\",\n"
               " \"mean_abs_error_m\": {\"x\": %.5f, \"y\": %.5f},\n"
               " \"sd_abs_error_m\": {\"x\": %.5f, \"y\": %.5f},\n"
               " \"mean_error_m\": {\"x\": %.5f, \"y\": %.5f},\n"
               " \"target_met\": %s, \"target\": \"world mean abs error <= 0.005 m in x and y\",\n",
               opt.scenario.c_str(), round ? "round" : "iss",
               static_cast<unsigned long long>(opt.seed), opt.duration_s, world_x.n, world_x.mean(),
               world_y.mean(), world_x.sd(), world_y.sd(), world_x.bias(), world_y.bias(),
               met ? "true" : "false");
  std::fprintf(f,
               " \"relative_to_handrail\": {\"frame\": \"the body in the filter's map against "
               "the body in the true handrail frame\", \"samples\": %.0f,\n"
               "   \"mean_abs_m\": {\"x\": %.5f, \"y\": %.5f}, \"sd_abs_m\": {\"x\": %.5f, "
               "\"y\": %.5f},\n"
               "   \"mean_m\": {\"x\": %.5f, \"y\": %.5f}},\n"
               " \"gp_mean_abs_error_m\": {\"x\": %.5f, \"y\": %.5f},\n"
               " \"gp_error\": {\"m\": %.3f, \"deg\": %.2f},\n",
               rel_x.n, rel_x.mean(), rel_y.mean(), rel_x.sd(), rel_y.sd(), rel_x.bias(),
               rel_y.bias(), gp_x.mean(), gp_y.mean(), opt.gp_bias_m, opt.gp_bias_deg);
  std::fprintf(f,
               " \"map\": \"%s\", \"survey_sigma\": {\"m\": %.4f, \"deg\": %.3f},\n"
               " \"survey_error\": {\"position_m\": [%.5f, %.5f, %.5f], \"attitude_deg\": %.4f},\n",
               opt.survey ? "surveyed" : "first sightings", opt.survey ? opt.survey_sigma_m : 0.0,
               opt.survey ? opt.survey_sigma_deg : 0.0, survey_dp.x(), survey_dp.y(), survey_dp.z(),
               survey_dtheta.norm() * 180.0 / kPi);
  std::fprintf(
      f,
      " \"handrail_accepted\": %u, \"handrail_no_end_accepted\": %u, \"handrail_rejected_gate\": "
      "%u,\n"
      " \"handrail_unusable\": %llu, \"gp_accepted\": %u, \"gp_held_off\": %llu, \"map_valid\": "
      "%s, \"figure\": \"%s\"}\n",
      r.handrail_accepted, r.handrail_no_end_accepted, r.handrail_rejected_gate,
      static_cast<unsigned long long>(r.task.handrail_unusable), r.gp_accepted,
      static_cast<unsigned long long>(r.task.gp_held_off), r.map_valid ? "true" : "false",
      png.c_str());
  std::fclose(f);
  std::printf(
      "dynamic test: %.0f s, %.0f samples, handrail map %s\n"
      "  world frame:            mean abs error x %.1f mm (sd %.1f), y %.1f mm (sd %.1f)\n"
      "  relative to the handrail: mean abs error x %.1f mm (sd %.1f), y %.1f mm (sd %.1f)\n"
      "  GP (world):             mean abs error x %.1f mm, y %.1f mm\n%s\n%s\n",
      opt.duration_s, world_x.n, opt.survey ? "surveyed" : "from the first sightings",
      1e3 * world_x.mean(), 1e3 * world_x.sd(), 1e3 * world_y.mean(), 1e3 * world_y.sd(),
      1e3 * rel_x.mean(), 1e3 * rel_x.sd(), 1e3 * rel_y.mean(), 1e3 * rel_y.sd(), 1e3 * gp_x.mean(),
      1e3 * gp_y.mean(), json.c_str(), png.c_str());
  return 0;
}
