#include "fsw_app/frame_publisher.hpp"

namespace fsw_app {

FramePublisher::FramePublisher(LcmHub& hub, const hal::Clock& clock, std::uint32_t max_width,
                               std::uint32_t max_height, hal::DepthDataListener& next)
    : clock_(clock),
      max_width_(max_width),
      max_height_(max_height),
      next_(next),
      publisher_(hub, channel::kDepthFrame,
                 depth_frame_encoded_size(static_cast<std::size_t>(max_width) * max_height)) {
  reserve_points(&msg_, static_cast<std::size_t>(max_width) * max_height);
}

void FramePublisher::on_new_data(const hal::DepthFrame& frame) {
  // The estimator's path comes first; publishing is for the other readers.
  next_.on_new_data(frame);
  if (frame.points == nullptr || frame.width == 0 || frame.height == 0 ||
      frame.width > max_width_ || frame.height > max_height_) {
    return;
  }
  to_msg(frame, &msg_);
  msg_.utime = clock_.now_us();
  if (publisher_.publish(msg_)) {
    published_.fetch_add(1);
  } else {
    failures_.fetch_add(1);
  }
}

}  // namespace fsw_app
