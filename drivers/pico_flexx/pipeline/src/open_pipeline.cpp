// Start-up only: the calibration file's reader allocates and reports in
// strings, which the frame path never does.
#include "pico_flexx/raw_depth_pipeline.hpp"
#include "tof/calibration_io.hpp"

namespace pico_flexx {

std::unique_ptr<RawDepthPipeline> open_raw_depth_pipeline(const std::string& calibration_path,
                                                          const PipelineConfig& config,
                                                          const hal::Clock& clock,
                                                          std::string* error) {
  tof::Calibration calibration;
  if (!tof::load_calibration_file(calibration_path, &calibration, error)) return nullptr;
  auto pipeline = std::make_unique<RawDepthPipeline>(calibration, config, clock);
  if (pipeline->init_status() != PipelineStatus::kOk) {
    *error = calibration_path +
             ": the ToF processing refused it: " + to_string(pipeline->init_status()) + " (" +
             tof::to_string(pipeline->processor_status()) + ")";
    return nullptr;
  }
  return pipeline;
}

}  // namespace pico_flexx
