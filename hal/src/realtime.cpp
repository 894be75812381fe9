#include "hal/realtime.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>

namespace hal {

const char* to_string(RealtimeStatus status) {
  switch (status) {
    case RealtimeStatus::kNotRequested:
      return "NOT_REQUESTED";
    case RealtimeStatus::kGranted:
      return "GRANTED";
    case RealtimeStatus::kNotPermitted:
      return "NOT_PERMITTED";
    case RealtimeStatus::kInvalid:
      return "INVALID";
    case RealtimeStatus::kFailed:
      return "FAILED";
  }
  return "UNKNOWN";
}

RealtimeStatus request_realtime_priority(int priority) {
  if (priority == 0) return RealtimeStatus::kNotRequested;
  if (priority < sched_get_priority_min(SCHED_FIFO) ||
      priority > sched_get_priority_max(SCHED_FIFO)) {
    return RealtimeStatus::kInvalid;
  }
  sched_param param{};
  param.sched_priority = priority;
  const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  if (rc == 0) return RealtimeStatus::kGranted;
  return rc == EPERM ? RealtimeStatus::kNotPermitted : RealtimeStatus::kFailed;
}

bool lower_thread_priority(int nice) {
  if (nice <= 0 || nice > 19) return false;
  const auto tid = static_cast<id_t>(syscall(SYS_gettid));
  errno = 0;
  const int now = getpriority(PRIO_PROCESS, tid);
  if (now == -1 && errno != 0) return false;
  return setpriority(PRIO_PROCESS, tid, now + nice) == 0;
}

}  // namespace hal
