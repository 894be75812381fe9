#include "load_run_config.hpp"

#include <cstdio>
#include <string>

#include "frame_receive_buffer.hpp"

namespace fsw_app {

std::optional<int> load_run_config(const Options& opt, AppConfig* cfg) {
  std::string error;
  if (!load_app_config(opt.config, cfg, &error)) {
    std::fprintf(stderr, "fsw_app: %s\n", error.c_str());
    return 2;
  }
  if (!opt.lcm_url.empty()) cfg->lcm_url = opt.lcm_url;
  // Frames of 0.73 MB arrive over udpm as a dozen datagrams at once: with
  // the kernel's default receive buffer (about 200 kB) most frames lose
  // one. A process that hears them (an estimator fed over udpm, or a log
  // of this process's own frames) asks LCM for a 4 MB buffer unless the
  // URL names one, and says so when the kernel will not grant that much.
  const bool sends_frames =
      (opt.runs(kCameraTask) && (opt.publish_frames || !opt.runs(kEstimatorTask))) ||
      !opt.frames_from_log.empty();
  const bool estimator_fed_over_lcm =
      opt.runs(kEstimatorTask) && !opt.runs(kCameraTask) && opt.frames_from_log.empty();
  if (estimator_fed_over_lcm || (!opt.log.empty() && sends_frames)) {
    if (!with_frame_receive_buffer(&cfg->lcm_url, &error)) {
      if (!opt.log.empty() && sends_frames) {
        // Recording frames that would be lost is refused outright.
        std::fprintf(stderr,
                     "fsw_app: %s; or record in-process with --lcm-url memq:// (--log "
                     "still records every message)\n",
                     error.c_str());
        return 2;
      }
      std::fprintf(stderr, "fsw_app: %s\n", error.c_str());
    }
  }
  if (!opt.handrail.empty()) {
    const float length = cfg->estimator.handrail.bar_length_m;
    cfg->estimator.handrail = opt.handrail == "iss" ? estimator::iss_handrail(length)
                                                    : estimator::paper_round_handrail(length);
  }
  if (!opt.arm_port.empty()) cfg->ports.servo_port = opt.arm_port;
  if (!opt.gripper_port.empty()) cfg->ports.gripper_port = opt.gripper_port;
  return std::nullopt;
}

}  // namespace fsw_app
