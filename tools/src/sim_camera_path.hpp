#pragma once
// The simulated camera as the tools drive it, one frame at a time, on
// either path: "depth" (the depth renderer) or "raw" (raw phase frames
// through the robot's ToF processing, on the calibration file the
// simulated unit writes), exactly as fsw_app --hal sim wires it.
#include <memory>
#include <string>
#include <vector>

#include "hal/clock.hpp"
#include "pico_flexx/raw_depth_pipeline.hpp"
#include "sim_hal/scenario.hpp"
#include "sim_hal/simulated_camera.hpp"

namespace tools {

class SimCameraPath final : public hal::DepthDataListener {
 public:
  // `scenario` must outlive this. The frames are stamped f * period_us.
  explicit SimCameraPath(const sim_hal::Scenario& scenario);

  // Opens the camera on `use_case`; for "raw" the unit's calibration goes
  // to `calibration_path` and the processing reads it back from there.
  bool open(const std::string& path, const std::string& calibration_path,
            const std::string& use_case, std::string* error);

  // Renders the next pose; false after the last. `frame` views a copy
  // owned by this object, valid until the next call.
  bool next(hal::DepthFrame* frame);

  const tof::RawFrame* last_raw_frame() const { return camera_.last_raw_frame(); }
  const pico_flexx::RawDepthPipeline* pipeline() const { return pipeline_.get(); }

  void on_new_data(const hal::DepthFrame& frame) override;

 private:
  hal::ManualClock stamp_clock_;
  hal::MonotonicClock timing_clock_;
  sim_hal::SimulatedCamera camera_;
  std::unique_ptr<pico_flexx::RawDepthPipeline> pipeline_;
  std::vector<hal::DepthPoint> points_;
  hal::DepthFrame frame_;
  bool got_frame_ = false;
  std::int64_t period_us_ = 200000;
};

}  // namespace tools
