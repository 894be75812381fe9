#pragma once
// What a run reports of the camera read through the royale API
// (pico_flexx/royale_depth_camera.hpp): royale hides the driver beneath it,
// so the account is what royale handed on and how its capture times were
// put on the host's clock.
#include <cstdint>
#include <string>

#include "pico_flexx/royale_depth_camera.hpp"

namespace fsw_app {

struct RoyalePathReport {
  pico_flexx::RoyaleFrameCounts frames;
  std::string capture_clock;  // SAME, MAPPED or UNKNOWN (no frame)
  // The emulated camera's own count of frames it made (sent and dropped
  // for want of a transfer); -1 for a real camera.
  std::int64_t frames_made_by_camera = -1;
};

inline RoyalePathReport royale_path_report(const pico_flexx::RoyaleDepthCamera& camera) {
  RoyalePathReport r;
  r.frames = camera.counts();
  r.capture_clock = pico_flexx::to_string(camera.capture_clock());
  return r;
}

}  // namespace fsw_app
