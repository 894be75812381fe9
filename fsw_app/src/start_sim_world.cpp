#include "start_sim_world.hpp"

#include <cstdio>

namespace fsw_app {

std::optional<int> start_sim_world(const Options& opt, const AppConfig& cfg, LcmHub& hub,
                                   const hal::Clock& clock, SimWorld* out) {
  out->servo_port = cfg.ports.servo_port;
  out->gripper_port = cfg.ports.gripper_port;
  if (!opt.needs_sim_world()) return std::nullopt;
#ifdef HRP_WITH_SIM
  std::string error;
  if (!sim_hal::load_scenario(opt.scenario, &out->scenario, &error)) {
    std::fprintf(stderr, "fsw_app: %s\n", error.c_str());
    return 2;
  }
  out->world = std::make_unique<HilWorld>(
      hub, out->scenario, cfg, hil_start_pose(out->scenario, cfg.T_body_cam, opt.seed), opt.seed,
      clock, hil_sensor_params(opt.gp_bias_m, opt.gp_bias_deg));
  if (!out->world->start(&error)) {
    std::fprintf(stderr, "fsw_app: simulated devices: %s\n", error.c_str());
    return 1;
  }
  out->servo_port = out->world->servo_path();
  out->gripper_port = out->world->gripper_path();
  if (!opt.runs(kArmTask)) {
    std::fprintf(stderr,
                 "fsw_app: simulated servos on %s, gripper board on %s (for an arm task in "
                 "another process: --hal real --tasks arm --arm-port %s --gripper-port %s)\n",
                 out->servo_port.c_str(), out->gripper_port.c_str(), out->servo_port.c_str(),
                 out->gripper_port.c_str());
  }
  return std::nullopt;
#else
  (void)hub;
  (void)clock;
  std::fprintf(stderr,
               "fsw_app: this build has no simulated HAL (a robot build); use --hal real\n");
  return 2;
#endif
}

}  // namespace fsw_app
