#include "sim_hal/simulated_camera.hpp"

#include <chrono>

#include "tof/calibration_io.hpp"

namespace sim_hal {

using hal::CameraStatus;

SimulatedCamera::SimulatedCamera(const Scenario& scenario, const hal::Clock& clock, Pacing pacing)
    : scenario_(scenario),
      clock_(clock),
      pacing_(pacing),
      intrinsics_(pico_flexx_intrinsics()),
      renderer_(intrinsics_, scenario.sensor),
      points_(static_cast<std::size_t>(intrinsics_.width) * intrinsics_.height),
      unit_calibration_(simulated_calibration(intrinsics_, kUnitSeed)) {}

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

bool SimulatedCamera::write_unit_calibration(const std::string& path, std::string* error) const {
  return tof::write_calibration_file(path, unit_calibration_, error);
}

CameraStatus SimulatedCamera::set_raw_pipeline(pico_flexx::RawDepthPipeline* pipeline) {
  if (capturing_) return CameraStatus::kDeviceIsBusy;
  std::lock_guard<std::mutex> lock(render_mutex_);
  pipeline_ = pipeline;
  if (pipeline_ == nullptr) return CameraStatus::kSuccess;
  pipeline_->set_listener(&processed_);
  if (!raw_renderer_) {
    raw_renderer_ = std::make_unique<RawRenderer>(intrinsics_, scenario_.sensor,
                                                  RawRenderSettings{}, unit_calibration_);
    raw_frame_ = std::make_unique<tof::RawFrame>();
  }
  return CameraStatus::kSuccess;
}

void SimulatedCamera::deliver(hal::DepthFrame frame, std::int64_t now_us) {
  if (tamper_) {
    // The tamper edits the camera's own buffer: the processed points are
    // copied there first (0.77 MB, well under a millisecond).
    if (frame.points != points_.data()) {
      std::copy(frame.points, frame.points + points_.size(), points_.begin());
      frame.points = points_.data();
    }
    tamper_->tamper(now_us, &frame, &points_);
  }
  if (listener_) listener_->on_new_data(frame);
}

void SimulatedCamera::ProcessedFrames::on_new_data(const hal::DepthFrame& frame) {
  camera_.deliver(frame, camera_.frame_time_us_);
}

CameraStatus SimulatedCamera::render_and_deliver(std::size_t index) {
  std::lock_guard<std::mutex> lock(render_mutex_);
  const std::int64_t now_us = clock_.now_us();
  const Eigen::Isometry3d T_world_cam =
      pose_source_ ? pose_source_->T_world_cam(now_us) : scenario_.T_world_cam[index];
  if (pipeline_ == nullptr) {
    renderer_.render(scenario_.scene, T_world_cam, scenario_.seed, index, &points_);
    deliver(hal::DepthFrame{index, now_us, intrinsics_.width, intrinsics_.height, points_.data()},
            now_us);
    return CameraStatus::kSuccess;
  }
  // The raw path: the imager's phase images, then the robot's processing,
  // which delivers through processed_.
  const tof::Mode mode = use_case_->raw_frames == 9 ? tof::Mode::kMode9 : tof::Mode::kMode5;
  raw_renderer_->render(scenario_.scene, T_world_cam, mode, use_case_->max_exposure_us,
                        scenario_.seed, index, raw_frame_.get());
  raw_frame_->frame_id = index;
  raw_frame_->capture_time_us = now_us;
  frame_time_us_ = now_us;
  (void)pipeline_->on_raw_frame(*raw_frame_);  // its counts say what became of it
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
