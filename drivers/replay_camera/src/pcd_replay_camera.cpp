#include "replay_camera/pcd_replay_camera.hpp"

#include <dirent.h>

#include <algorithm>
#include <chrono>

namespace replay_camera {

PcdReplayCamera::PcdReplayCamera(std::string folder, const hal::Clock& clock, bool loop,
                                 std::uint64_t max_points)
    : folder_(std::move(folder)), clock_(clock), loop_(loop), max_points_(max_points) {}

PcdReplayCamera::~PcdReplayCamera() {
  (void)stop_capture();
}

bool PcdReplayCamera::load(std::string* error) {
  DIR* dir = opendir(folder_.c_str());
  if (!dir) {
    *error = folder_ + ": cannot open the folder of recorded frames";
    return false;
  }
  std::vector<std::string> names;
  while (const dirent* e = readdir(dir)) {
    const std::string name = e->d_name;
    if (name.size() > 4 && name.compare(name.size() - 4, 4, ".pcd") == 0) names.push_back(name);
  }
  closedir(dir);
  std::sort(names.begin(), names.end());
  frames_.clear();
  skipped_.clear();
  for (const std::string& name : names) {
    formats::PcdFrame f;
    std::string why;
    if (formats::read_pcd(folder_ + "/" + name, &f, &why, max_points_)) {
      frames_.push_back(std::move(f));
    } else {
      skipped_ += why + "\n";
    }
  }
  if (frames_.empty()) {
    *error = folder_ + ": no readable .pcd frames" + (skipped_.empty() ? "" : ":\n" + skipped_);
    return false;
  }
  *error = skipped_;
  return true;
}

hal::CameraStatus PcdReplayCamera::initialize() {
  if (initialized_) return hal::CameraStatus::kDeviceAlreadyInitialized;
  if (frames_.empty()) return hal::CameraStatus::kDataNotFound;
  initialized_ = true;
  std::size_t n = 0;
  use_case_ = &hal::use_cases(&n)[0];
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus PcdReplayCamera::set_use_case(const char* name) {
  if (!initialized_) return hal::CameraStatus::kDeviceNotInitialized;
  if (capturing_) return hal::CameraStatus::kDeviceIsBusy;
  const hal::UseCase* u = name ? hal::find_use_case(name) : nullptr;
  if (!u) return hal::CameraStatus::kUseCaseNotSupported;
  use_case_ = u;
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus PcdReplayCamera::current_use_case(const hal::UseCase** use_case) const {
  if (!initialized_) return hal::CameraStatus::kDeviceNotInitialized;
  *use_case = use_case_;
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus PcdReplayCamera::set_exposure_mode(hal::ExposureMode) {
  return initialized_ ? hal::CameraStatus::kSuccess : hal::CameraStatus::kDeviceNotInitialized;
}

hal::CameraStatus PcdReplayCamera::set_exposure_time(std::uint32_t) {
  // A recording's exposure is what it was.
  return hal::CameraStatus::kExposureModeInvalid;
}

hal::CameraStatus PcdReplayCamera::register_data_listener(hal::DepthDataListener* listener) {
  if (capturing_) return hal::CameraStatus::kDeviceIsBusy;
  listener_ = listener;
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus PcdReplayCamera::lens_parameters(hal::LensParameters* lens) const {
  *lens = hal::LensParameters{};  // not recorded in a PCD file
  return hal::CameraStatus::kNoCalibrationData;
}

hal::CameraStatus PcdReplayCamera::max_frame_size(std::uint32_t* width,
                                                  std::uint32_t* height) const {
  *width = *height = 0;
  for (const formats::PcdFrame& f : frames_) {
    *width = std::max(*width, f.width);
    *height = std::max(*height, f.height);
  }
  return frames_.empty() ? hal::CameraStatus::kDataNotFound : hal::CameraStatus::kSuccess;
}

void PcdReplayCamera::capture_loop() {
  const auto period = std::chrono::microseconds(frame_period_us(*use_case_));
  auto due = std::chrono::steady_clock::now();
  std::size_t k = 0;
  while (capturing_.load()) {
    if (k == frames_.size()) {
      if (!loop_) break;
      k = 0;
    }
    const std::uint64_t id = delivered_.load();
    if (listener_) listener_->on_new_data(frames_[k].view(id, clock_.now_us()));
    delivered_.fetch_add(1);
    ++k;
    due += period;
    std::this_thread::sleep_until(due);
  }
  capturing_ = false;
}

hal::CameraStatus PcdReplayCamera::start_capture() {
  if (!initialized_) return hal::CameraStatus::kDeviceNotInitialized;
  if (capturing_) return hal::CameraStatus::kDeviceIsBusy;
  if (thread_.joinable()) thread_.join();
  capturing_ = true;
  thread_ = std::thread(&PcdReplayCamera::capture_loop, this);
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus PcdReplayCamera::stop_capture() {
  capturing_ = false;
  if (thread_.joinable()) thread_.join();
  return hal::CameraStatus::kSuccess;
}

}  // namespace replay_camera
