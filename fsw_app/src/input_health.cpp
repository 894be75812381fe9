#include "fsw_app/input_health.hpp"

namespace fsw_app {

static_assert(kInputRejectKinds <= hrp::input_health_t::MAX_REASONS,
              "input_health_t holds every refusal reason");

InputHealthReporter::InputHealthReporter(LcmHub& hub, const std::string& tasks)
    : hub_(hub), publisher_(hub, channel::kInputHealth, 16384) {
  std::size_t n = 0;
  const ChannelInput* inputs = hub_.inputs(&n);
  msg_.tasks = tasks;
  msg_.num_channels = static_cast<std::int32_t>(n);
  msg_.channel.resize(n);
  for (std::size_t k = 0; k < n; ++k) msg_.channel[k] = inputs[k].channel;
  msg_.num_reasons = kInputRejectKinds;
  msg_.reason.resize(kInputRejectKinds);
  for (int r = 0; r < kInputRejectKinds; ++r) {
    msg_.reason[r] = to_string(static_cast<InputReject>(r));
  }
  msg_.accepted.assign(n, 0);
  msg_.rejected.assign(n, std::vector<std::int64_t>(kInputRejectKinds, 0));
}

const hrp::input_health_t& InputHealthReporter::refresh(std::int64_t now_us) {
  std::size_t n = 0;
  const ChannelInput* inputs = hub_.inputs(&n);
  msg_.utime = now_us;
  for (std::size_t k = 0; k < n && k < msg_.channel.size(); ++k) {
    const InputCounts& c = *inputs[k].counts;
    msg_.accepted[k] = static_cast<std::int64_t>(c.accepted.load());
    for (int r = 0; r < kInputRejectKinds; ++r) {
      msg_.rejected[k][r] = static_cast<std::int64_t>(c.rejected[r].load());
    }
  }
  return msg_;
}

bool InputHealthReporter::publish(std::int64_t now_us) {
  return publisher_.publish(refresh(now_us));
}

std::int64_t InputHealthReporter::rejected_total() const {
  std::int64_t n = 0;
  for (const auto& row : msg_.rejected) {
    for (std::int64_t c : row) n += c;
  }
  return n;
}

}  // namespace fsw_app
