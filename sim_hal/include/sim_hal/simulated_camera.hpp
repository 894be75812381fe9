#pragma once
// The simulated Pico Flexx behind the hal depth-camera interface: renders a
// scenario's frames and hands them to the registered listener, either paced
// at the use case's frame rate (real time) or as fast as possible, or one
// at a time with capture_next() for lock-step simulation and tests.
//
// Two paths to the listener: the depth renderer (tof_sensor.hpp, depth
// with modelled sensor effects; the default until a pipeline is set) or,
// once set_raw_pipeline() is called, the raw path: the raw renderer
// (tof_raw_renderer.hpp) makes the unit's phase images and the robot's own
// ToF processing (pico_flexx/raw_depth_pipeline.hpp) turns them into the
// depth frames the listener gets. The unit's calibration is the camera's
// truth; write_unit_calibration() puts it in the file the robot's side
// reads at start-up.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "hal/clock.hpp"
#include "hal/depth_camera.hpp"
#include "pico_flexx/raw_depth_pipeline.hpp"
#include "sim_hal/scenario.hpp"
#include "sim_hal/tof_raw_renderer.hpp"
#include "sim_hal/tof_sensor.hpp"

namespace sim_hal {

// Where the camera is at a moment: a simulated robot's pose, for closed-loop
// runs in which the camera follows the robot instead of a fixed list.
class CameraPoseSource {
 public:
  virtual ~CameraPoseSource() = default;
  virtual Eigen::Isometry3d T_world_cam(std::int64_t now_us) = 0;
};

// A chance to spoil a rendered frame before delivery (fault injection:
// occlusion, corrupt frames). May change the points and the header.
class FrameTamper {
 public:
  virtual ~FrameTamper() = default;
  virtual void tamper(std::int64_t now_us, hal::DepthFrame* frame,
                      std::vector<hal::DepthPoint>* points) = 0;
};

class SimulatedCamera final : public hal::DepthCamera {
 public:
  enum class Pacing : std::uint8_t { kRealTime, kAsFastAsPossible };

  // The scenario must outlive the camera; `clock` stamps the frames.
  SimulatedCamera(const Scenario& scenario, const hal::Clock& clock, Pacing pacing);
  ~SimulatedCamera() override;

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
  bool is_connected() const override { return true; }
  bool is_capturing() const override { return capturing_.load(); }

  // Renders the next pose and delivers it on the caller's thread. Returns
  // DATA_NOT_FOUND after the last pose, DEVICE_IS_BUSY while capturing.
  [[nodiscard]] hal::CameraStatus capture_next();
  std::size_t frames_delivered() const { return next_frame_.load(); }
  // The scenario's poses; unbounded with a pose source.
  std::size_t frame_count() const;

  // Set before start_capture; neither is owned.
  void set_pose_source(CameraPoseSource* source) { pose_source_ = source; }
  void set_tamper(FrameTamper* tamper) { tamper_ = tamper; }

  // The simulated unit's calibration (simulated_calibration with
  // kUnitSeed) and writing it as the unit's calibration file.
  static constexpr std::uint64_t kUnitSeed = 7;
  const tof::Calibration& unit_calibration() const { return unit_calibration_; }
  bool write_unit_calibration(const std::string& path, std::string* error) const;
  // The raw path through `pipeline` (not owned; built by the robot's side
  // from the calibration file). Set before start_capture; nullptr goes back
  // to the depth renderer. DEVICE_IS_BUSY while capturing.
  [[nodiscard]] hal::CameraStatus set_raw_pipeline(pico_flexx::RawDepthPipeline* pipeline);
  bool raw_path() const { return pipeline_ != nullptr; }
  // The raw path's last raw frame (nullptr on the depth path), for tools
  // that record it; valid until the next frame is rendered.
  const tof::RawFrame* last_raw_frame() const { return pipeline_ ? raw_frame_.get() : nullptr; }

 private:
  // The pipeline's listener: applies the tamper to the processed frame,
  // then hands it to the registered listener.
  class ProcessedFrames final : public hal::DepthDataListener {
   public:
    explicit ProcessedFrames(SimulatedCamera& camera) : camera_(camera) {}
    void on_new_data(const hal::DepthFrame& frame) override;

   private:
    SimulatedCamera& camera_;
  };

  hal::CameraStatus render_and_deliver(std::size_t index);
  void deliver(hal::DepthFrame frame, std::int64_t now_us);
  void capture_loop();

  const Scenario& scenario_;
  const hal::Clock& clock_;
  Pacing pacing_;
  CameraIntrinsics intrinsics_;
  DepthRenderer renderer_;
  std::vector<hal::DepthPoint> points_;
  const hal::UseCase* use_case_ = nullptr;
  bool initialized_ = false;
  hal::ExposureMode exposure_mode_ = hal::ExposureMode::kAutomatic;
  hal::DepthDataListener* listener_ = nullptr;
  std::atomic<bool> capturing_{false};
  std::atomic<std::size_t> next_frame_{0};
  std::thread thread_;
  std::mutex render_mutex_;
  CameraPoseSource* pose_source_ = nullptr;
  FrameTamper* tamper_ = nullptr;
  // The raw path, built when a pipeline is set.
  tof::Calibration unit_calibration_;
  pico_flexx::RawDepthPipeline* pipeline_ = nullptr;
  std::unique_ptr<RawRenderer> raw_renderer_;
  std::unique_ptr<tof::RawFrame> raw_frame_;
  ProcessedFrames processed_{*this};
  std::int64_t frame_time_us_ = 0;  // the frame being processed's render time
};

}  // namespace sim_hal
