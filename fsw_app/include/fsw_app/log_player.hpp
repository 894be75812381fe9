#pragma once
// Replays a recorded run into this process's estimator: plays the
// DEPTH_FRAME and ROBOT_POSE messages of an LCM log onto the hub at the
// pace they were recorded, as lcm-logplayer would, but in process (so it
// works on memq:// too) and with the messages' monotonic times moved to
// this run's clock, so that latencies and frame gaps read as they did.
// Other channels (the recorded estimates among them) are not played: the
// estimator's own results must not mix with the old ones.
//
// A DEPTH_FRAME event that does not decode is played as recorded, so the
// receiving camera counts it as corrupt, and the rest play on. Damaged
// bytes between events are skipped to the next sync word and counted
// (LCM's reader drops the event just before them too).
#include <lcm/lcm-cpp.hpp>

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "fsw_app/lcm_hub.hpp"
#include "hal/clock.hpp"
#include "hrp/depth_frame_t.hpp"
#include "hrp/robot_pose_t.hpp"

namespace fsw_app {

struct LogPlayerCounts {
  std::uint64_t frames = 0;      // DEPTH_FRAME messages played
  std::uint64_t bad_frames = 0;  // of those, played as recorded because they did not decode
  std::uint64_t poses = 0;       // ROBOT_POSE messages played
  std::uint64_t other = 0;       // events of other channels, not played
  std::uint64_t damaged = 0;     // stretches of damaged bytes skipped (each loses an event)
};

class LogPlayer {
 public:
  LogPlayer(LcmHub& hub, std::string path, const hal::Clock& clock, std::uint32_t max_width,
            std::uint32_t max_height);
  ~LogPlayer();

  // Reads the log through once: false, with *error naming the file and
  // what to do, when it will not open or holds no DEPTH_FRAME message.
  bool open(std::string* error);
  std::uint64_t frames_in_log() const { return frames_in_log_; }

  void start();  // plays on a thread of its own, once through
  void stop();
  bool finished() const { return finished_.load(); }
  LogPlayerCounts counts() const;

 private:
  void play();
  void wait_until(std::int64_t t_us);
  void play_event(const lcm::LogEvent& event);
  // A recorded monotonic time on this run's clock; the first message
  // played fixes the offset.
  std::int64_t to_this_run(std::int64_t recorded_us);
  template <typename Msg>
  void publish_encoded(const std::string& channel, const Msg& msg);

  LcmHub& hub_;
  std::string path_;
  const hal::Clock& clock_;
  std::size_t max_points_;
  std::uint64_t frames_in_log_ = 0;
  hrp::depth_frame_t frame_;
  hrp::robot_pose_t pose_{};
  std::vector<std::uint8_t> buffer_;
  bool have_offset_ = false;
  std::int64_t time_offset_us_ = 0;  // this run's clock minus the recording's
  std::atomic<std::uint64_t> frames_{0}, bad_frames_{0}, poses_{0}, other_{0}, damaged_{0};
  std::atomic<bool> running_{false}, finished_{false};
  std::thread thread_;
};

}  // namespace fsw_app
