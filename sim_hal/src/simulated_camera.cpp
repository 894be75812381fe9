#include "sim_hal/simulated_camera.hpp"

#include <chrono>

namespace sim_hal {

using hal::CameraStatus;

SimulatedCamera::SimulatedCamera(const Scenario& scenario, const hal::Clock& clock, Pacing pacing)
    : scenario_(scenario),
      clock_(clock),
      pacing_(pacing),
      intrinsics_(pico_flexx_intrinsics()),
      renderer_(intrinsics_, scenario.sensor),
      points_(static_cast<std::size_t>(intrinsics_.width) * intrinsics_.height) {}

SimulatedCamera::~SimulatedCamera() {
  (void)stop_capture();
}

CameraStatus SimulatedCamera::initialize() {
  if (initialized_) return CameraStatus::kDeviceAlreadyInitialized;
  initialized_ = true;
  // As the real camera: the first use case until told otherwise.
  std::size_t n = 0;
  use_case_ = &hal::use_cases(&n)[0];
  return CameraStatus::kSuccess;
}

CameraStatus SimulatedCamera::set_use_case(const char* name) {
  if (!initialized_) return CameraStatus::kDeviceNotInitialized;
  if (capturing_) return CameraStatus::kDeviceIsBusy;
  const hal::UseCase* use_case = name ? hal::find_use_case(name) : nullptr;
  if (!use_case) return CameraStatus::kUseCaseNotSupported;
  use_case_ = use_case;
  return CameraStatus::kSuccess;
}

CameraStatus SimulatedCamera::current_use_case(const hal::UseCase** use_case) const {
  if (!initialized_) return CameraStatus::kDeviceNotInitialized;
  *use_case = use_case_;
  return CameraStatus::kSuccess;
}

CameraStatus SimulatedCamera::set_exposure_mode(hal::ExposureMode mode) {
  if (!initialized_) return CameraStatus::kDeviceNotInitialized;
  exposure_mode_ = mode;
  return CameraStatus::kSuccess;
}

CameraStatus SimulatedCamera::set_exposure_time(std::uint32_t exposure_us) {
  if (!initialized_) return CameraStatus::kDeviceNotInitialized;
  if (exposure_mode_ != hal::ExposureMode::kManual) return CameraStatus::kExposureModeInvalid;
  if (exposure_us == 0 || exposure_us > use_case_->max_exposure_us)
    return CameraStatus::kExposureTimeNotSupported;
  return CameraStatus::kSuccess;  // the sensor model's auto exposure stands in for it
}

CameraStatus SimulatedCamera::register_data_listener(hal::DepthDataListener* listener) {
  if (capturing_) return CameraStatus::kDeviceIsBusy;
  listener_ = listener;
  return CameraStatus::kSuccess;
}

CameraStatus SimulatedCamera::lens_parameters(hal::LensParameters* lens) const {
  *lens = intrinsics_.lens;
  return CameraStatus::kSuccess;
}

CameraStatus SimulatedCamera::max_frame_size(std::uint32_t* width, std::uint32_t* height) const {
  *width = intrinsics_.width;
  *height = intrinsics_.height;
  return CameraStatus::kSuccess;
}

std::size_t SimulatedCamera::frame_count() const {
  return pose_source_ ? static_cast<std::size_t>(-1) : scenario_.T_world_cam.size();
}

CameraStatus SimulatedCamera::render_and_deliver(std::size_t index) {
  std::lock_guard<std::mutex> lock(render_mutex_);
  const std::int64_t now_us = clock_.now_us();
  const Eigen::Isometry3d T_world_cam =
      pose_source_ ? pose_source_->T_world_cam(now_us) : scenario_.T_world_cam[index];
  renderer_.render(scenario_.scene, T_world_cam, scenario_.seed, index, &points_);
  hal::DepthFrame frame{index, now_us, intrinsics_.width, intrinsics_.height, points_.data()};
  if (tamper_) tamper_->tamper(now_us, &frame, &points_);
  if (listener_) listener_->on_new_data(frame);
  return CameraStatus::kSuccess;
}

CameraStatus SimulatedCamera::capture_next() {
  if (!initialized_) return CameraStatus::kDeviceNotInitialized;
  if (capturing_) return CameraStatus::kDeviceIsBusy;
  const std::size_t index = next_frame_.load();
  if (index >= frame_count()) return CameraStatus::kDataNotFound;
  const CameraStatus status = render_and_deliver(index);
  next_frame_ = index + 1;
  return status;
}

void SimulatedCamera::capture_loop() {
  const auto period = std::chrono::microseconds(hal::frame_period_us(*use_case_));
  auto due = std::chrono::steady_clock::now();
  while (capturing_) {
    const std::size_t index = next_frame_.load();
    if (index >= frame_count()) break;
    (void)render_and_deliver(index);
    next_frame_ = index + 1;
    if (pacing_ == Pacing::kRealTime) {
      due += period;
      std::this_thread::sleep_until(due);
    }
  }
  capturing_ = false;
}

CameraStatus SimulatedCamera::start_capture() {
  if (!initialized_) return CameraStatus::kDeviceNotInitialized;
  if (capturing_) return CameraStatus::kDeviceIsBusy;
  if (thread_.joinable()) thread_.join();  // a run that reached its last frame
  capturing_ = true;
  thread_ = std::thread(&SimulatedCamera::capture_loop, this);
  return CameraStatus::kSuccess;
}

CameraStatus SimulatedCamera::stop_capture() {
  capturing_ = false;
  if (thread_.joinable()) thread_.join();
  return CameraStatus::kSuccess;
}

}  // namespace sim_hal
