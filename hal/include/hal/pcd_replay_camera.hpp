#pragma once
// A depth camera that plays a folder of recorded PCD frames at the use
// case's frame rate, in file-name order, looping: what royale does when
// it opens a recording in place of a camera. A file that will not read is
// reported and skipped; the others play.
#include <atomic>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "hal/clock.hpp"
#include "hal/depth_camera.hpp"
#include "hal/pcd_io.hpp"

namespace hal {

class PcdReplayCamera final : public DepthCamera {
 public:
  PcdReplayCamera(std::string folder, const Clock& clock, bool loop = true);
  ~PcdReplayCamera() override;

  // Reads every *.pcd in the folder. False when none is usable; *error
  // then says why, and names each bad file (one per line) either way.
  bool load(std::string* error);
  std::size_t frame_count() const { return frames_.size(); }
  const std::string& skipped() const { return skipped_; }

  [[nodiscard]] CameraStatus initialize() override;
  [[nodiscard]] CameraStatus set_use_case(const char* name) override;
  [[nodiscard]] CameraStatus current_use_case(const UseCase** use_case) const override;
  [[nodiscard]] CameraStatus set_exposure_mode(ExposureMode mode) override;
  [[nodiscard]] CameraStatus set_exposure_time(std::uint32_t exposure_us) override;
  [[nodiscard]] CameraStatus register_data_listener(DepthDataListener* listener) override;
  [[nodiscard]] CameraStatus start_capture() override;
  [[nodiscard]] CameraStatus stop_capture() override;
  [[nodiscard]] CameraStatus lens_parameters(LensParameters* lens) const override;
  [[nodiscard]] CameraStatus max_frame_size(std::uint32_t* width,
                                            std::uint32_t* height) const override;
  bool is_connected() const override { return !frames_.empty(); }
  bool is_capturing() const override { return capturing_.load(); }
  std::uint64_t frames_delivered() const { return delivered_.load(); }

 private:
  void capture_loop();

  std::string folder_;
  const Clock& clock_;
  bool loop_;
  std::vector<PcdFrame> frames_;
  std::string skipped_;
  const UseCase* use_case_ = nullptr;
  bool initialized_ = false;
  DepthDataListener* listener_ = nullptr;
  std::atomic<bool> capturing_{false};
  std::atomic<std::uint64_t> delivered_{0};
  std::thread thread_;
};

}  // namespace hal
