#pragma once
// The hardware-in-loop world of a --hal sim run (hil_world.hpp): built
// before the camera and the arm's drivers because both are opened on it
// (the rendered camera, the simulated devices' ptys). A robot build has no
// simulated HAL; there the run keeps the configured ports.
#include <memory>
#include <optional>
#include <string>

#include "app_options.hpp"
#include "fsw_app/app_config.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "hal/clock.hpp"
#ifdef HRP_WITH_SIM
#include "hil_world.hpp"
#include "sim_hal/scenario.hpp"
#endif

namespace sim_hal {
struct Scenario;
}

namespace fsw_app {

class HilWorld;

struct SimWorld {
  // The arm's ports: the configuration's, or the simulated devices' ptys.
  std::string servo_port, gripper_port;
#ifdef HRP_WITH_SIM
  sim_hal::Scenario scenario;
  std::unique_ptr<HilWorld> world;  // after the scenario: it reads it to the end

  // The world, nullptr when no task here needs it; the scenario it flies.
  HilWorld* hil() const {
    return world.get();
  }
  const sim_hal::Scenario* scene() const {
    return &scenario;
  }
#else
  HilWorld* hil() const {
    return nullptr;
  }
  const sim_hal::Scenario* scene() const {
    return nullptr;
  }
#endif
};

// Fills *out: the configured ports, and when a task here needs the
// simulated HAL's camera or devices (Options::needs_sim_world), the
// scenario loaded and the world started on its devices. Returns an exit
// status after printing why, when the run cannot go on: 2 for a bad
// scenario or a robot build asked for --hal sim, 1 for devices that would
// not start.
std::optional<int> start_sim_world(const Options& opt, const AppConfig& cfg, LcmHub& hub,
                                   const hal::Clock& clock, SimWorld* out);

}  // namespace fsw_app
