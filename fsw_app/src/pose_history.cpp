#include "fsw_app/pose_history.hpp"

#include "fsw_app/msg_convert.hpp"

namespace fsw_app {

const char* to_string(PoseAtStatus status) {
  switch (status) {
    case PoseAtStatus::kInterpolated:
      return "INTERPOLATED";
    case PoseAtStatus::kNewest:
      return "NEWEST";
    case PoseAtStatus::kNoPose:
      return "NO_POSE";
    case PoseAtStatus::kTooOld:
      return "TOO_OLD";
    case PoseAtStatus::kTooNew:
      return "TOO_NEW";
    case PoseAtStatus::kGap:
      return "GAP";
    case PoseAtStatus::kLost:
      return "LOST";
  }
  return "UNKNOWN";
}

void PoseHistory::deliver(const void* data, std::uint32_t size, std::int64_t now_us) {
  box_.deliver(data, size, now_us);
  const std::uint64_t seq = box_.read(&incoming_);
  if (seq == seen_) return;  // refused: counted by the box, nothing held changes
  seen_ = seq;
  Stamped s;
  s.utime = incoming_.utime;
  const Eigen::Isometry3d T = from_msg(incoming_.T_world_body);
  s.p_world = T.translation();
  s.q_world_body = Eigen::Quaterniond(T.linear());
  s.lost = incoming_.lost;
  std::lock_guard<std::mutex> lock(mutex_);
  // The box takes an older pose only from a restarted sender (its clock
  // began again): what is held belongs to the old clock.
  if (count_ > 0 && s.utime <= at(count_ - 1).utime) count_ = 0;
  if (count_ == kCapacity) {
    oldest_ = (oldest_ + 1) % kCapacity;
    --count_;
  }
  ring_[static_cast<std::size_t>((oldest_ + count_) % kCapacity)] = s;
  ++count_;
}

const PoseHistory::Stamped& PoseHistory::at(int k) const {
  return ring_[static_cast<std::size_t>((oldest_ + k) % kCapacity)];
}

int PoseHistory::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return count_;
}

PoseAtStatus PoseHistory::pose_at(std::int64_t t_us, Eigen::Isometry3d* T_world_body) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (count_ == 0) return PoseAtStatus::kNoPose;
  const Stamped& newest = at(count_ - 1);
  if (t_us >= newest.utime) {
    if (t_us - newest.utime > kMaxAhead_us) return PoseAtStatus::kTooNew;
    if (newest.lost) return PoseAtStatus::kLost;
    T_world_body->setIdentity();
    T_world_body->linear() = newest.q_world_body.toRotationMatrix();
    T_world_body->translation() = newest.p_world;
    return PoseAtStatus::kNewest;
  }
  if (t_us < at(0).utime) return PoseAtStatus::kTooOld;
  // The first held pose after t: a binary search over the ring, by time.
  int lo = 0, hi = count_ - 1;  // at(lo) <= t < at(hi)
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    (at(mid).utime <= t_us ? lo : hi) = mid;
  }
  const Stamped& a = at(lo);
  const Stamped& b = at(hi);
  if (b.utime - a.utime > kMaxBracket_us) return PoseAtStatus::kGap;
  if (a.lost || b.lost) return PoseAtStatus::kLost;
  const double f = static_cast<double>(t_us - a.utime) / static_cast<double>(b.utime - a.utime);
  T_world_body->setIdentity();
  T_world_body->linear() = a.q_world_body.slerp(f, b.q_world_body).toRotationMatrix();
  T_world_body->translation() = a.p_world + f * (b.p_world - a.p_world);
  return PoseAtStatus::kInterpolated;
}

}  // namespace fsw_app
