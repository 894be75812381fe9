#include "hal/pcd_replay_camera.hpp"

#include <dirent.h>

#include <algorithm>
#include <chrono>

namespace hal {

PcdReplayCamera::PcdReplayCamera(std::string folder, const Clock& clock, bool loop)
    : folder_(std::move(folder)), clock_(clock), loop_(loop) {}

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
    PcdFrame f;
    std::string why;
    if (read_pcd(folder_ + "/" + name, &f, &why)) {
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

CameraStatus PcdReplayCamera::initialize() {
  if (initialized_) return CameraStatus::kDeviceAlreadyInitialized;
  if (frames_.empty()) return CameraStatus::kDataNotFound;
  initialized_ = true;
  std::size_t n = 0;
  use_case_ = &use_cases(&n)[0];
  return CameraStatus::kSuccess;
}

CameraStatus PcdReplayCamera::set_use_case(const char* name) {
  if (!initialized_) return CameraStatus::kDeviceNotInitialized;
  if (capturing_) return CameraStatus::kDeviceIsBusy;
  const UseCase* u = name ? find_use_case(name) : nullptr;
  if (!u) return CameraStatus::kUseCaseNotSupported;
  use_case_ = u;
  return CameraStatus::kSuccess;
}

CameraStatus PcdReplayCamera::current_use_case(const UseCase** use_case) const {
  if (!initialized_) return CameraStatus::kDeviceNotInitialized;
  *use_case = use_case_;
  return CameraStatus::kSuccess;
}

CameraStatus PcdReplayCamera::set_exposure_mode(ExposureMode) {
  return initialized_ ? CameraStatus::kSuccess : CameraStatus::kDeviceNotInitialized;
}

CameraStatus PcdReplayCamera::set_exposure_time(std::uint32_t) {
  // A recording's exposure is what it was.
  return CameraStatus::kExposureModeInvalid;
}

CameraStatus PcdReplayCamera::register_data_listener(DepthDataListener* listener) {
  if (capturing_) return CameraStatus::kDeviceIsBusy;
  listener_ = listener;
  return CameraStatus::kSuccess;
}

CameraStatus PcdReplayCamera::lens_parameters(LensParameters* lens) const {
  *lens = LensParameters{};  // not recorded in a PCD file
  return CameraStatus::kNoCalibrationData;
}

CameraStatus PcdReplayCamera::max_frame_size(std::uint32_t* width, std::uint32_t* height) const {
  *width = *height = 0;
  for (const PcdFrame& f : frames_) {
    *width = std::max(*width, f.width);
    *height = std::max(*height, f.height);
  }
  return frames_.empty() ? CameraStatus::kDataNotFound : CameraStatus::kSuccess;
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

CameraStatus PcdReplayCamera::start_capture() {
  if (!initialized_) return CameraStatus::kDeviceNotInitialized;
  if (capturing_) return CameraStatus::kDeviceIsBusy;
  if (thread_.joinable()) thread_.join();
  capturing_ = true;
  thread_ = std::thread(&PcdReplayCamera::capture_loop, this);
  return CameraStatus::kSuccess;
}

CameraStatus PcdReplayCamera::stop_capture() {
  capturing_ = false;
  if (thread_.joinable()) thread_.join();
  return CameraStatus::kSuccess;
}

}  // namespace hal
