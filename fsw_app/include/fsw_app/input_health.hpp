#pragma once
// INPUT_HEALTH: one process's input counts (LcmHub::inputs()) as a message,
// published once a second and at the end of the run. The message's arrays
// are sized once, after the tasks have subscribed: no allocation per
// publish.
#include <string>

#include "fsw_app/lcm_hub.hpp"
#include "hrp/input_health_t.hpp"

namespace fsw_app {

namespace channel {
inline constexpr const char* kInputHealth = "INPUT_HEALTH";
}  // namespace channel

class InputHealthReporter {
 public:
  // Call once every task has subscribed (the channel list is fixed then).
  InputHealthReporter(LcmHub& hub, const std::string& tasks);
  // The counts as they stand.
  const hrp::input_health_t& refresh(std::int64_t now_us);
  bool publish(std::int64_t now_us);
  // Messages rejected on every channel together.
  std::int64_t rejected_total() const;

 private:
  LcmHub& hub_;
  hrp::input_health_t msg_{};
  Publisher<hrp::input_health_t> publisher_;
};

}  // namespace fsw_app
