#include "fsw_app/input_health.hpp"

namespace fsw_app {

InputHealthReporter::InputHealthReporter(LcmHub& hub, const std::string& tasks)
    : hub_(hub), publisher_(hub, channel::kInputHealth, 8192) {
  std::size_t n = 0;
  const ChannelInput* inputs = hub_.inputs(&n);
  msg_.tasks = tasks;
  msg_.num_channels = static_cast<std::int32_t>(n);
  msg_.channel.resize(n);
  for (std::size_t k = 0; k < n; ++k) msg_.channel[k] = inputs[k].channel;
  for (auto* v : {&msg_.accepted, &msg_.undecodable, &msg_.trailing_bytes, &msg_.not_finite,
                  &msg_.out_of_range, &msg_.stale}) {
    v->assign(n, 0);
  }
}

const hrp::input_health_t& InputHealthReporter::refresh(std::int64_t now_us) {
  std::size_t n = 0;
  const ChannelInput* inputs = hub_.inputs(&n);
  msg_.utime = now_us;
  for (std::size_t k = 0; k < n && k < msg_.channel.size(); ++k) {
    const InputCounts& c = *inputs[k].counts;
    const auto rejected = [&c](InputReject r) {
      return static_cast<std::int64_t>(c.rejected[static_cast<int>(r)].load());
    };
    msg_.accepted[k] = static_cast<std::int64_t>(c.accepted.load());
    msg_.undecodable[k] = rejected(InputReject::kUndecodable);
    msg_.trailing_bytes[k] = rejected(InputReject::kTrailingBytes);
    msg_.not_finite[k] = rejected(InputReject::kNotFinite);
    msg_.out_of_range[k] = rejected(InputReject::kOutOfRange);
    msg_.stale[k] = rejected(InputReject::kStale);
  }
  return msg_;
}

bool InputHealthReporter::publish(std::int64_t now_us) {
  return publisher_.publish(refresh(now_us));
}

std::int64_t InputHealthReporter::rejected_total() const {
  std::int64_t n = 0;
  for (std::size_t k = 0; k < msg_.channel.size(); ++k) {
    n += msg_.undecodable[k] + msg_.trailing_bytes[k] + msg_.not_finite[k] + msg_.out_of_range[k] +
         msg_.stale[k];
  }
  return n;
}

}  // namespace fsw_app
