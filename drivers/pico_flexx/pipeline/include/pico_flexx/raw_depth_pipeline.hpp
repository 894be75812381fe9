#pragma once
// The stage between a Pico Flexx that delivers raw phase frames and the
// depth-camera interface's listener: raw frame in, the robot's ToF
// processing (tof/processor.hpp), the depth frame out to the registered
// hal::DepthDataListener, on the caller's (the camera's) thread.
//
// Any raw-frame source feeds it the same way: the simulator's raw renderer
// (sim_hal::SimulatedCamera on the raw path) and the USB driver. It
// also keeps what the run's summary reports: how long the processing took
// (median over the last kTimingWindow frames) and how many frames it
// dropped or found mostly invalid.
//
// Robot code: everything is sized at construction; on_raw_frame()
// allocates nothing, throws nothing and runs a bounded number of steps.
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "hal/clock.hpp"
#include "hal/depth_camera.hpp"
#include "tof/calibration.hpp"
#include "tof/processor.hpp"
#include "tof/raw_frame.hpp"

namespace pico_flexx {

struct PipelineConfig {
  tof::ProcessingConfig processing;
  // A delivered frame with fewer valid pixels than this share of the image
  // is counted as mostly invalid (it is still delivered: the estimator
  // decides what it can use).
  float mostly_invalid_below = 0.5f;
};

enum class PipelineStatus : std::uint8_t {
  kOk,             // processed and delivered
  kMostlyInvalid,  // delivered, but fewer valid pixels than mostly_invalid_below
  kDropped,        // the processing refused the frame (not delivered)
  kBadProcessor,   // init: the processor refused the calibration or config
  kBadConfig,      // init: mostly_invalid_below outside [0, 1]
};
const char* to_string(PipelineStatus status);

struct PipelineCounts {
  std::uint64_t frames_in = 0;
  std::uint64_t frames_delivered = 0;
  std::uint64_t frames_dropped = 0;         // the processing refused them
  std::uint64_t frames_mostly_invalid = 0;  // delivered with few valid pixels
  tof::ProcessStatus last_drop = tof::ProcessStatus::kOk;
  // Pixels by state, summed over every processed frame.
  std::uint64_t pixels_by_state[tof::kPixelStates] = {};
};

class RawDepthPipeline {
 public:
  // Processing times kept for the median.
  static constexpr std::size_t kTimingWindow = 1024;

  // `clock` times the processing (monotonic, injected).
  RawDepthPipeline(const tof::Calibration& calibration, const PipelineConfig& config,
                   const hal::Clock& clock);

  PipelineStatus init_status() const { return init_status_; }
  tof::ProcessStatus processor_status() const { return processor_.init_status(); }

  // Where depth frames go (not owned; nullptr: nowhere). Set before frames
  // flow; the frame is valid only during the listener's call.
  void set_listener(hal::DepthDataListener* listener) { listener_ = listener; }

  // Processes one raw frame and delivers its depth frame (kOk,
  // kMostlyInvalid) or drops it (kDropped, and on a failed init).
  PipelineStatus on_raw_frame(const tof::RawFrame& raw);

  // A snapshot; safe from any thread.
  PipelineCounts counts() const;
  // Median processing time of the last kTimingWindow frames in
  // microseconds; -1 before the first frame.
  std::int64_t processing_median_us() const;
  // The lens the processing's rays come from (the calibration's).
  const hal::LensParameters& lens() const { return lens_; }

 private:
  tof::Processor processor_;
  PipelineConfig config_;
  const hal::Clock& clock_;
  PipelineStatus init_status_ = PipelineStatus::kOk;
  hal::LensParameters lens_;
  hal::DepthDataListener* listener_ = nullptr;
  mutable std::mutex mutex_;  // counts_, the timing ring and its scratch
  PipelineCounts counts_;
  std::unique_ptr<std::int32_t[]> timing_us_;  // ring of kTimingWindow
  mutable std::unique_ptr<std::int32_t[]> scratch_us_;
  std::size_t timings_ = 0;  // written so far (the ring holds the last ones)
};

// Start-up: reads the unit's calibration file (tof/CALIBRATION.md) and
// builds the pipeline on it. nullptr, with *error naming the file (and for
// a malformed file its line and key), when the file is missing or bad or
// the processing refuses the calibration. Allocates: not for a frame path.
std::unique_ptr<RawDepthPipeline> open_raw_depth_pipeline(const std::string& calibration_path,
                                                          const PipelineConfig& config,
                                                          const hal::Clock& clock,
                                                          std::string* error);

}  // namespace pico_flexx
