#pragma once
// What the run itself watches and sends, over LCM like any other reader:
// the arm's state, the estimator's health, the approach, every estimate
// (the summary's sightings, wherever the estimator runs), the perch
// commands, and this process's input counts. Shared by the run loop and
// the end-of-run report.
#include "app_options.hpp"
#include "fsw_app/app_config.hpp"
#include "fsw_app/input_health.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "fsw_app/sighting_tally.hpp"
#include "hrp/approach_status_t.hpp"
#include "hrp/arm_state_t.hpp"
#include "hrp/estimator_health_t.hpp"
#include "hrp/perch_command_t.hpp"

namespace fsw_app {

struct RunWatch {
  // Made after the tasks have subscribed and before the hub starts: the
  // input counts' channel list is fixed once every subscription is made,
  // so input_health comes last.
  RunWatch(LcmHub& hub, const AppConfig& cfg, unsigned tasks)
      : sightings(cfg.estimator),
        command_pub(hub, channel::kPerchCommand),
        input_health(subscribed(hub), task_names(tasks)) {}
  RunWatch(const RunWatch&) = delete;
  RunWatch& operator=(const RunWatch&) = delete;

  Mailbox<hrp::arm_state_t> arm_box;
  Mailbox<hrp::estimator_health_t> health_box;
  Mailbox<hrp::approach_status_t> approach_box;
  SightingTally sightings;
  Publisher<hrp::perch_command_t> command_pub;
  InputHealthReporter input_health;

 private:
  // The run's own subscriptions; returns the hub for input_health.
  LcmHub& subscribed(LcmHub& hub) {
    hub.subscribe(channel::kArmState, &arm_box);
    hub.subscribe(channel::kEstimatorHealth, &health_box);
    hub.subscribe(channel::kApproachStatus, &approach_box);
    hub.subscribe(channel::kHandrailEstimate, &sightings);
    return hub;
  }
};

}  // namespace fsw_app
