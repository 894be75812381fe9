#include "fsw_app/lcm_hub.hpp"

#include <cstring>

#include "hal/realtime.hpp"

namespace fsw_app {

const hal::Clock& LcmHub::host_clock() {
  static const hal::MonotonicClock clock;
  return clock;
}

LcmHub::LcmHub(const std::string& url, const hal::Clock* clock)
    : url_(url), clock_(clock), lcm_(url) {}

LcmHub::~LcmHub() {
  stop();
}

bool LcmHub::publish_raw(const std::string& channel, const std::uint8_t* data, std::size_t size) {
  // LCM's publish is not documented as thread safe for every provider.
  std::lock_guard<std::mutex> lock(publish_mutex_);
  return lcm_.publish(channel, data, static_cast<unsigned int>(size)) == 0;
}

void LcmHub::subscribe_all(RawSink sink, void* user) {
  sink_ = sink;
  sink_user_ = user;
  lcm::Subscription* sub = lcm_.subscribeFunction(
      ".*",
      +[](const lcm::ReceiveBuffer* rbuf, const std::string& channel, LcmHub* hub) {
        try {
          hub->sink_(hub->sink_user_, channel, *rbuf);
        } catch (...) {
          hub->receiver_faults_.fetch_add(1, std::memory_order_relaxed);
        }
      },
      this);
  if (sub != nullptr) sub->setQueueCapacity(kSubscriptionQueue);
}

void LcmHub::register_input(const char* channel, const InputCounts* counts) {
  for (std::size_t k = 0; k < input_count_; ++k) {
    if (std::strcmp(inputs_[k].channel, channel) == 0) return;
  }
  // More channels than the table holds are still checked, only not listed;
  // the table is sized above every channel the program has.
  if (input_count_ < kMaxCheckedChannels) inputs_[input_count_++] = ChannelInput{channel, counts};
}

void LcmHub::start() {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this] {
    // Behind the flight tasks: a flood on the bus then costs the bus's own
    // latency (queued in LCM, kSubscriptionQueue deep), not the arm loop's
    // deadline. Nothing to do when the kernel refuses.
    (void)hal::lower_thread_priority(kDispatcherNice);
    while (running_.load()) lcm_.handleTimeout(50);
  });
}

void LcmHub::stop() {
  if (!running_.exchange(false)) return;
  if (thread_.joinable()) thread_.join();
}

}  // namespace fsw_app
