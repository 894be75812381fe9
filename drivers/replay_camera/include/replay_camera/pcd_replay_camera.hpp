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

#include "formats/pcd_io.hpp"
#include "hal/clock.hpp"
#include "hal/depth_camera.hpp"

namespace replay_camera {

class PcdReplayCamera final : public hal::DepthCamera {
 public:
  // `max_points`: the largest frame the receiver's buffers hold; a file
  // whose header claims more is skipped before its points are allocated.
  PcdReplayCamera(std::string folder, const hal::Clock& clock, bool loop = true,
                  std::uint64_t max_points = formats::kMaxPcdPoints);
  ~PcdReplayCamera() override;

  // Reads every *.pcd in the folder. False when none is usable; *error
  // then says why, and names each bad file (one per line) either way.
  bool load(std::string* error);
  std::size_t frame_count() const { return frames_.size(); }
  const std::string& skipped() const { return skipped_; }

  [[nodiscard]] hal::CameraStatus initialize() override;
  [[nodiscard]] hal::CameraStatus set_use_case(const char* name) override;
  [[nodiscard]] hal::CameraStatus current_use_case(const hal::UseCase** use_case) const override;
  [[nodiscard]] hal::CameraStatus set_exposure_mode(hal::ExposureMode mode) override;
  [[nodiscard]] hal::CameraStatus set_exposure_time(std::uint32_t exposure_us) override;
  [[nodiscard]] hal::CameraStatus register_data_listener(hal::DepthDataListener* listener) override;
  [[nodiscard]] hal::CameraStatus start_capture() override;
  [[nodiscard]] hal::CameraStatus stop_capture() override;
  [[nodiscard]] hal::CameraStatus lens_parameters(hal::LensParameters* lens) const override;
  [[nodiscard]] hal::CameraStatus max_frame_size(std::uint32_t* width,
                                                 std::uint32_t* height) const override;
  bool is_connected() const override { return !frames_.empty(); }
  bool is_capturing() const override { return capturing_.load(); }
  std::uint64_t frames_delivered() const { return delivered_.load(); }

 private:
  void capture_loop();

  std::string folder_;
  const hal::Clock& clock_;
  bool loop_;
  std::uint64_t max_points_;
  std::vector<formats::PcdFrame> frames_;
  std::string skipped_;
  const hal::UseCase* use_case_ = nullptr;
  bool initialized_ = false;
  hal::DepthDataListener* listener_ = nullptr;
  std::atomic<bool> capturing_{false};
  std::atomic<std::uint64_t> delivered_{0};
  std::thread thread_;
};

}  // namespace replay_camera
