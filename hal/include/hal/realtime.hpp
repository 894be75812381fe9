#pragma once
// Real-time scheduling for a time-critical thread (the arm's control loop,
// the simulated devices standing in for hardware). Asked for, never
// assumed: without the privilege (CAP_SYS_NICE or an rtprio limit) the
// thread keeps the normal scheduler and the caller reports it.
#include <cstdint>

namespace hal {

enum class RealtimeStatus : std::uint8_t {
  kNotRequested,  // priority 0: the normal scheduler by choice
  kGranted,       // SCHED_FIFO at the priority asked for
  kNotPermitted,  // EPERM: no privilege; the normal scheduler
  kInvalid,       // the priority is outside what SCHED_FIFO allows
  kFailed,        // any other error
};

const char* to_string(RealtimeStatus status);

// Puts the calling thread under SCHED_FIFO at `priority` (1..99); 0 asks
// for nothing.
RealtimeStatus request_realtime_priority(int priority);

// Lowers the calling thread's weight under the normal scheduler by `nice`
// (1..19; Linux threads each have their own nice value). Needs no
// privilege. False, errno kept, when the kernel refused.
bool lower_thread_priority(int nice);

}  // namespace hal
