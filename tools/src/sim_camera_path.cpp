#include "sim_camera_path.hpp"

#include <algorithm>

namespace tools {

SimCameraPath::SimCameraPath(const sim_hal::Scenario& scenario)
    : camera_(scenario, stamp_clock_, sim_hal::SimulatedCamera::Pacing::kAsFastAsPossible) {
  if (scenario.frame_rate_hz > 0) {
    period_us_ = static_cast<std::int64_t>(1e6 / scenario.frame_rate_hz);
  }
}

bool SimCameraPath::open(const std::string& path, const std::string& calibration_path,
                         const std::string& use_case, std::string* error) {
  if (path != "raw" && path != "depth") {
    *error = "the camera path is raw or depth, not '" + path + "'";
    return false;
  }
  if (camera_.initialize() != hal::CameraStatus::kSuccess ||
      camera_.set_use_case(use_case.c_str()) != hal::CameraStatus::kSuccess) {
    *error = "the simulated camera would not take use case " + use_case;
    return false;
  }
  if (path == "raw") {
    if (!camera_.write_unit_calibration(calibration_path, error)) return false;
    pipeline_ = pico_flexx::open_raw_depth_pipeline(calibration_path, pico_flexx::PipelineConfig{},
                                                    timing_clock_, error);
    if (!pipeline_) return false;
    if (camera_.set_raw_pipeline(pipeline_.get()) != hal::CameraStatus::kSuccess) {
      *error = "the simulated camera refused the raw path";
      return false;
    }
  }
  return camera_.register_data_listener(this) == hal::CameraStatus::kSuccess;
}

bool SimCameraPath::next(hal::DepthFrame* frame) {
  stamp_clock_.set_us(static_cast<std::int64_t>(camera_.frames_delivered()) * period_us_);
  got_frame_ = false;
  if (camera_.capture_next() != hal::CameraStatus::kSuccess) return false;
  if (!got_frame_) {
    // The processing dropped it: an empty frame of the right size, as the
    // estimator would see a frame with nothing valid.
    points_.assign(static_cast<std::size_t>(tof::kPixels), hal::DepthPoint{});
    frame_ = hal::DepthFrame{camera_.frames_delivered() - 1, stamp_clock_.now_us(), tof::kWidthPx,
                             tof::kHeightPx, points_.data()};
  }
  *frame = frame_;
  return true;
}

void SimCameraPath::on_new_data(const hal::DepthFrame& frame) {
  const std::size_t n = static_cast<std::size_t>(frame.width) * frame.height;
  points_.assign(frame.points, frame.points + n);
  frame_ = frame;
  frame_.points = points_.data();
  got_frame_ = true;
}

}  // namespace tools
