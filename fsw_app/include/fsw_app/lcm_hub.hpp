#pragma once
// One LCM instance shared by the process's tasks. memq:// (the unit tests)
// delivers only within one instance, and udpm wants one socket per process,
// so the tasks share this hub: one dispatcher thread decodes each message
// into its mailbox (the newest value per channel), and any task publishes.
// Publishing encodes into the publisher's buffer, sized once: no
// allocation per message on our side.
#include <lcm/lcm-cpp.hpp>

#include <utility>

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "fsw_app/input_checks.hpp"
#include "fsw_app/input_gates.hpp"
#include "hal/clock.hpp"

namespace fsw_app {

// The gates a decoded, checked message passes on its way into a receiver
// (input_gates.hpp): the time against the receiver's clock, then the
// sender's counter and the channel's rate. Each refusal is counted.
// Dispatcher thread only.
template <typename Msg>
class InputGates {
 public:
  bool dated_ok(const Msg& m, std::int64_t now_us, InputCounts* counts) const {
    if (!dated_ahead(newest_time_us(m), now_us)) return true;
    counts->count_rejected(InputReject::kFuture);
    return false;
  }
  // After every other test: a message refused here has taken no token.
  bool counter_and_rate_ok(const Msg& m, std::int64_t now_us, InputCounts* counts) {
    std::int64_t seq = 0;
    if (sequence_of(m, &seq) && !sequence_.admit(seq)) {
      counts->count_rejected(InputReject::kSequence);
      return false;
    }
    if (!rate_.admit(now_us)) {
      counts->count_rejected(InputReject::kRateLimited);
      return false;
    }
    return true;
  }

 private:
  SequenceGate sequence_;
  RateGate rate_{rate_bound(static_cast<const Msg*>(nullptr))};
};

// The newest message on a channel, with a count so a reader can tell a new
// one from the one it already has. Each message is decoded into a copy
// aside and checked (input_checks.hpp, input_gates.hpp): only a whole,
// finite, in-range message, not dated ahead of the receiver's clock, no
// older than the held one and within the channel's rate replaces it; a
// rejected one leaves the held message as it was and is counted by reason.
template <typename Msg>
class Mailbox {
 public:
  // Copies the newest message out; returns its sequence number (0: none yet).
  std::uint64_t read(Msg* out) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (sequence_ != 0) *out = msg_;
    return sequence_;
  }
  std::uint64_t sequence() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return sequence_;
  }
  const InputCounts& input_counts() const { return counts_; }

  // Dispatcher side (one thread: incoming_ and the gates need no lock of
  // their own). now_us: the receiver's clock, or kNoReceiverClock.
  void deliver(const void* data, std::uint32_t size, std::int64_t now_us) {
    InputReject why = InputReject::kUndecodable;
    if (!decode_and_check(data, size, &incoming_, &why)) {
      counts_.count_rejected(why);
      return;
    }
    if (!gates_.dated_ok(incoming_, now_us, &counts_)) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (sequence_ != 0 && !is_fresh(incoming_.utime, msg_.utime)) {
      counts_.count_rejected(InputReject::kStale);
      return;
    }
    if (!gates_.counter_and_rate_ok(incoming_, now_us, &counts_)) return;
    // A swap, not a copy: string fields keep their buffers, no allocation.
    std::swap(msg_, incoming_);
    ++sequence_;
    counts_.accepted.fetch_add(1, std::memory_order_relaxed);
  }

 private:
  mutable std::mutex mutex_;
  Msg msg_{};
  Msg incoming_{};
  std::uint64_t sequence_ = 0;
  InputGates<Msg> gates_;
  InputCounts counts_;
};

// A fixed queue of decoded messages for a channel where every message
// counts (commands: each is validated and answered, so two arriving within
// one cycle must not become one). Holds `Capacity` messages; when full, the
// oldest is overwritten and counted (a newer command, an abort above all,
// matters more than an older one). No allocation: messages without
// variable-length fields only. Messages are checked as a Mailbox's are,
// except for age against the held one: commands are judged in order by the
// arm's own rules, samples by their counter (input_gates.hpp).
template <typename Msg, std::size_t Capacity>
class MessageQueue {
  static_assert(Capacity > 0, "a queue holds at least one message");

 public:
  // Takes the oldest message out; false when there is none.
  bool pop(Msg* out) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (count_ == 0) return false;
    *out = slots_[head_];
    head_ = (head_ + 1) % Capacity;
    --count_;
    return true;
  }
  std::uint64_t overflows() const { return overflows_.load(); }
  const InputCounts& input_counts() const { return counts_; }

  // Dispatcher side. Decoded aside first, so a malformed message leaves
  // the queue as it was.
  void deliver(const void* data, std::uint32_t size, std::int64_t now_us) {
    InputReject why = InputReject::kUndecodable;
    if (!decode_and_check(data, size, &incoming_, &why)) {
      counts_.count_rejected(why);
      return;
    }
    if (!gates_.dated_ok(incoming_, now_us, &counts_) ||
        !gates_.counter_and_rate_ok(incoming_, now_us, &counts_)) {
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (count_ == Capacity) {
      head_ = (head_ + 1) % Capacity;
      --count_;
      ++overflows_;
    }
    slots_[(head_ + count_) % Capacity] = incoming_;
    ++count_;
    counts_.accepted.fetch_add(1, std::memory_order_relaxed);
  }

 private:
  std::mutex mutex_;
  Msg slots_[Capacity]{};
  Msg incoming_{};
  InputGates<Msg> gates_;
  std::size_t head_ = 0, count_ = 0;
  std::atomic<std::uint64_t> overflows_{0};
  InputCounts counts_;
};

// The input counts of one subscribed channel (the first receiver's, when
// several in one process take the same channel: they see the same bytes).
struct ChannelInput {
  const char* channel = nullptr;  // a channel:: constant or a caller's string that outlives the hub
  const InputCounts* counts = nullptr;
};
constexpr std::size_t kMaxCheckedChannels = 16;

// Every receiver is called inside the hub's containment: whatever it
// throws (a generated decoder, an allocation) ends there and is counted in
// receiver_faults(), and the dispatcher goes on.
//
// LCM holds at most 30 messages a subscription waiting for dispatch by
// default and drops the rest without counting them. Under a flood (40,000
// junk messages a second) real messages were lost there, and 2 % of the
// flood went uncounted; kSubscriptionQueue lets the dispatcher catch up
// instead (LCM's own delivery of a message costs about 3 us here, the
// receiver's refusal well under one: tools/bench/bus_bench).
class LcmHub {
 public:
  // Receivers judge messages' times against `clock` (the robot's clock, or
  // a simulation's); the default is the host's monotonic clock.
  explicit LcmHub(const std::string& url) : LcmHub(url, &host_clock()) {}
  LcmHub(const std::string& url, const hal::Clock& clock) : LcmHub(url, &clock) {}
  // A hub replaying a recorded run: its messages are dated in the past's
  // clock, so receivers judge neither time nor rate (counters and content
  // still).
  static constexpr struct ReplayTag {
  } kReplay{};
  LcmHub(const std::string& url, ReplayTag) : LcmHub(url, nullptr) {}
  ~LcmHub();
  bool good() const { return lcm_.good(); }
  const std::string& url() const { return url_; }

  // Each message on `channel` goes, still encoded, to receiver->deliver(data,
  // size, now_us) on the dispatcher thread: a Mailbox, a MessageQueue, or
  // anything with that member (the LCM frame source). A receiver with
  // input_counts() has them listed in inputs(). Subscribe before start().
  template <typename Receiver>
  void subscribe(const char* channel, Receiver* receiver) {
    if constexpr (has_input_counts<Receiver>(0)) register_input(channel, &receiver->input_counts());
    deliveries_.push_back(std::make_unique<Delivery>(Delivery{this, receiver}));
    lcm::Subscription* sub = lcm_.subscribeFunction(
        channel,
        +[](const lcm::ReceiveBuffer* rbuf, const std::string&, Delivery* del) {
          try {
            static_cast<Receiver*>(del->receiver)
                ->deliver(rbuf->data, rbuf->data_size, del->hub->receiver_now_us());
          } catch (...) {
            del->hub->receiver_faults_.fetch_add(1, std::memory_order_relaxed);
          }
        },
        deliveries_.back().get());
    if (sub != nullptr) sub->setQueueCapacity(kSubscriptionQueue);
  }

  static constexpr int kSubscriptionQueue = 2048;
  // The dispatcher thread's nice value above the tasks' (start()).
  static constexpr int kDispatcherNice = 10;

  // The receivers' clock now, or kNoReceiverClock for a replay hub.
  std::int64_t receiver_now_us() const {
    return clock_ != nullptr ? clock_->now_us() : kNoReceiverClock;
  }
  // Exceptions that reached the hub from a receiver or the raw sink.
  std::uint64_t receiver_faults() const { return receiver_faults_.load(); }

  // The checked channels of this process, in subscription order.
  const ChannelInput* inputs(std::size_t* count) const {
    *count = input_count_;
    return inputs_;
  }

  // Publishes already-encoded bytes; thread safe.
  bool publish_raw(const std::string& channel, const std::uint8_t* data, std::size_t size);

  // Every message on every channel to `sink` (the run's log). Once.
  using RawSink = void (*)(void* user, const std::string& channel, const lcm::ReceiveBuffer& rbuf);
  void subscribe_all(RawSink sink, void* user);

  // Runs the dispatcher on a thread of its own until stop().
  void start();
  void stop();
  // Or dispatches on the caller's thread, waiting up to timeout_ms.
  int handle(int timeout_ms) { return lcm_.handleTimeout(timeout_ms); }
  lcm::LCM& lcm() { return lcm_; }

 private:
  LcmHub(const std::string& url, const hal::Clock* clock);
  static const hal::Clock& host_clock();

  // What a subscription's callback needs: its receiver and the hub. Made
  // at subscription (initialisation), kept for the hub's life.
  struct Delivery {
    LcmHub* hub;
    void* receiver;
  };

  std::string url_;
  const hal::Clock* clock_;
  lcm::LCM lcm_;
  std::vector<std::unique_ptr<Delivery>> deliveries_;
  std::atomic<std::uint64_t> receiver_faults_{0};
  std::mutex publish_mutex_;
  std::atomic<bool> running_{false};
  std::thread thread_;
  RawSink sink_ = nullptr;
  void* sink_user_ = nullptr;
  ChannelInput inputs_[kMaxCheckedChannels];
  std::size_t input_count_ = 0;

  template <typename R>
  static constexpr auto has_input_counts(int) -> decltype(std::declval<R&>().input_counts(), true) {
    return true;
  }
  template <typename R>
  static constexpr bool has_input_counts(...) {
    return false;
  }
  void register_input(const char* channel, const InputCounts* counts);
};

// Encodes one message type into a buffer sized at construction.
template <typename Msg>
class Publisher {
 public:
  Publisher(LcmHub& hub, std::string channel, std::size_t capacity = 4096)
      : hub_(hub), channel_(std::move(channel)), buffer_(capacity) {}
  bool publish(const Msg& msg) {
    const int n = msg.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
    if (n < 0) {
      ++failures_;
      return false;
    }
    return hub_.publish_raw(channel_, buffer_.data(), static_cast<std::size_t>(n));
  }
  std::uint64_t failures() const { return failures_; }

 private:
  LcmHub& hub_;
  std::string channel_;
  std::vector<std::uint8_t> buffer_;
  std::uint64_t failures_ = 0;
};

// Channel names.
namespace channel {
inline constexpr const char* kHandrailEstimate = "HANDRAIL_ESTIMATE";
inline constexpr const char* kPerchCommand = "PERCH_COMMAND";
inline constexpr const char* kApproachStatus = "APPROACH_STATUS";
inline constexpr const char* kArmState = "ARM_STATE";
inline constexpr const char* kEstimatorHealth = "ESTIMATOR_HEALTH";
inline constexpr const char* kRobotPose = "ROBOT_POSE";
inline constexpr const char* kBodyVelocityCommand = "BODY_VELOCITY_COMMAND";
inline constexpr const char* kDepthFrame = "DEPTH_FRAME";
inline constexpr const char* kImuSample = "IMU_SAMPLE";
inline constexpr const char* kGpPose = "GP_POSE";
inline constexpr const char* kLocalizationHealth = "LOCALIZATION_HEALTH";
// The simulator's true pose: for scoring only, no robot-side task reads it.
inline constexpr const char* kTruthPose = "TRUTH_POSE";
}  // namespace channel

}  // namespace fsw_app
