#include "fsw_app/log_player.hpp"

#include <algorithm>
#include <chrono>

#include "fsw_app/depth_frame_msg.hpp"

namespace fsw_app {

namespace {
// A pause in the recording longer than this (the recorder stopped, say)
// is played as this long.
constexpr std::int64_t kLongestGapUs = 2000000;
// Reads a log's events, past damage. LCM's reader returns null both at the
// end and where an event is not followed by a sync word (damaged bytes): it
// then drops that event, and the next call scans forward to the next sync
// word. It also returns null at "the end" when an event's header claims
// more data than the file holds (a corrupt datalen such as 0x7ffffff0): it
// reads to the end of the file looking for it. So an end of file that is
// not just after the last good event is damage too: the reader goes back
// to one byte past where the bad event began and scans on from there, once
// after each good event (a scan that finds nothing more ends the log, so
// trailing garbage costs one scan, not one per byte). Each stretch is
// counted. Every retry starts further into the file than the last, so
// this ends.
class EventReader {
 public:
  explicit EventReader(lcm::LogFile& log) : log_(log) {}

  const lcm::LogEvent* next(std::uint64_t* damaged) {
    for (;;) {
      std::FILE* f = log_.getFilePtr();
      if (f == nullptr) return nullptr;
      if (const lcm::LogEvent* e = log_.readNextEvent()) {
        good_end_ = std::ftell(f);
        may_retry_ = true;
        return e;
      }
      if (std::ferror(f)) return nullptr;
      if (!std::feof(f)) {
        ++*damaged;  // bytes that were no event, skipped to the next sync word
        continue;
      }
      // At the end: truly, or after an event that claimed too much?
      std::fseek(f, 0, SEEK_END);
      const long retry_from = good_end_ + 1;
      if (!may_retry_ || good_end_ < 0 || retry_from >= std::ftell(f)) return nullptr;
      ++*damaged;
      may_retry_ = false;
      std::clearerr(f);
      std::fseek(f, retry_from, SEEK_SET);
    }
  }

 private:
  lcm::LogFile& log_;
  long good_end_ = 0;  // just after the last event read whole (the file's start at first)
  bool may_retry_ = true;
};

}  // namespace

LogPlayer::LogPlayer(LcmHub& hub, std::string path, const hal::Clock& clock,
                     std::uint32_t max_width, std::uint32_t max_height)
    : hub_(hub),
      path_(std::move(path)),
      clock_(clock),
      max_points_(static_cast<std::size_t>(max_width) * max_height),
      buffer_(depth_frame_encoded_size(max_points_)) {
  reserve_points(&frame_, max_points_);
}

LogPlayer::~LogPlayer() {
  stop();
}

bool LogPlayer::open(std::string* error) {
  lcm::LogFile log(path_, "r");
  if (!log.good()) {
    *error = path_ + ": cannot open it as an LCM log";
    return false;
  }
  frames_in_log_ = 0;
  std::uint64_t damaged = 0;
  EventReader reader(log);
  while (const lcm::LogEvent* e = reader.next(&damaged)) {
    if (e->channel == channel::kDepthFrame) ++frames_in_log_;
  }
  if (frames_in_log_ == 0) {
    *error = path_ +
             ": no DEPTH_FRAME message in this log; record one with fsw_app --publish-frames "
             "--log FILE (or lcm-logger while the camera task publishes frames)";
    return false;
  }
  return true;
}

void LogPlayer::start() {
  if (running_.exchange(true)) return;
  finished_ = false;
  thread_ = std::thread([this] { play(); });
}

void LogPlayer::stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
}

LogPlayerCounts LogPlayer::counts() const {
  return {frames_.load(), bad_frames_.load(), poses_.load(), other_.load(), damaged_.load()};
}

void LogPlayer::wait_until(std::int64_t t_us) {
  // In slices, so that stop() is heard within 50 ms.
  while (running_.load()) {
    const std::int64_t left_us = t_us - clock_.now_us();
    if (left_us <= 0) return;
    std::this_thread::sleep_for(std::chrono::microseconds(std::min<std::int64_t>(left_us, 50000)));
  }
}

void LogPlayer::play() {
  lcm::LogFile log(path_, "r");
  std::int64_t last_event_us = -1, play_at_us = clock_.now_us();
  std::uint64_t damaged = 0;
  EventReader reader(log);
  while (running_.load() && log.good()) {
    const lcm::LogEvent* e = reader.next(&damaged);
    damaged_.store(damaged);
    if (e == nullptr) break;
    // Event stamps are the recorder's receive times; only their
    // differences are used.
    if (last_event_us >= 0) {
      play_at_us += std::clamp<std::int64_t>(e->timestamp - last_event_us, 0, kLongestGapUs);
    }
    last_event_us = e->timestamp;
    if (e->channel != channel::kDepthFrame && e->channel != channel::kRobotPose) {
      other_.fetch_add(1);
      continue;
    }
    wait_until(play_at_us);
    if (!running_.load()) break;
    play_event(*e);
  }
  finished_ = true;
}

std::int64_t LogPlayer::to_this_run(std::int64_t recorded_us) {
  if (!have_offset_) {
    time_offset_us_ = clock_.now_us() - recorded_us;
    have_offset_ = true;
  }
  return recorded_us + time_offset_us_;
}

template <typename Msg>
void LogPlayer::publish_encoded(const std::string& channel, const Msg& msg) {
  const int n = msg.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
  if (n > 0) hub_.publish_raw(channel, buffer_.data(), static_cast<std::size_t>(n));
}

void LogPlayer::play_event(const lcm::LogEvent& e) {
  const auto* data = static_cast<const std::uint8_t*>(e.data);
  const auto size = static_cast<std::size_t>(std::max(e.datalen, 0));
  // A message that does not decode goes out as recorded: its receiver
  // counts it.
  if (e.channel == channel::kDepthFrame) {
    frames_.fetch_add(1);
    if (decode_depth_frame(data, size, max_points_, &frame_) != FrameMsgStatus::kOk) {
      bad_frames_.fetch_add(1);
      hub_.publish_raw(e.channel, data, size);
      return;
    }
    frame_.capture_utime = to_this_run(frame_.capture_utime);
    frame_.utime = to_this_run(frame_.utime);
    publish_encoded(e.channel, frame_);
    return;
  }
  poses_.fetch_add(1);
  if (pose_.decode(data, 0, static_cast<int>(size)) < 0) {
    hub_.publish_raw(e.channel, data, size);
    return;
  }
  pose_.utime = to_this_run(pose_.utime);
  publish_encoded(e.channel, pose_);
}

}  // namespace fsw_app
