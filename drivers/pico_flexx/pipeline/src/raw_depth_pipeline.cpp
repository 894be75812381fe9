#include "pico_flexx/raw_depth_pipeline.hpp"

#include <algorithm>

namespace pico_flexx {

const char* to_string(PipelineStatus status) {
  switch (status) {
    case PipelineStatus::kOk:
      return "OK";
    case PipelineStatus::kMostlyInvalid:
      return "MOSTLY_INVALID";
    case PipelineStatus::kDropped:
      return "DROPPED";
    case PipelineStatus::kBadProcessor:
      return "BAD_PROCESSOR";
    case PipelineStatus::kBadConfig:
      return "BAD_CONFIG";
  }
  return "UNKNOWN";
}

RawDepthPipeline::RawDepthPipeline(const tof::Calibration& calibration,
                                   const PipelineConfig& config, const hal::Clock& clock)
    : processor_(calibration, config.processing),
      config_(config),
      clock_(clock),
      lens_(calibration.lens),
      timing_us_(new std::int32_t[kTimingWindow]()),
      scratch_us_(new std::int32_t[kTimingWindow]()) {
  if (processor_.init_status() != tof::ProcessStatus::kOk) {
    init_status_ = PipelineStatus::kBadProcessor;
  } else if (!(config.mostly_invalid_below >= 0.0f && config.mostly_invalid_below <= 1.0f)) {
    init_status_ = PipelineStatus::kBadConfig;
  }
}

PipelineStatus RawDepthPipeline::on_raw_frame(const tof::RawFrame& raw) {
  if (init_status_ != PipelineStatus::kOk) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++counts_.frames_in;
    ++counts_.frames_dropped;
    return init_status_;
  }
  const std::int64_t start_us = clock_.now_us();
  hal::DepthFrame frame;
  const tof::ProcessStatus status = processor_.process(raw, &frame);
  const std::int64_t took_us = clock_.now_us() - start_us;
  PipelineStatus result = PipelineStatus::kOk;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++counts_.frames_in;
    if (status != tof::ProcessStatus::kOk) {
      ++counts_.frames_dropped;
      counts_.last_drop = status;
      return PipelineStatus::kDropped;
    }
    timing_us_[timings_ % kTimingWindow] =
        static_cast<std::int32_t>(std::clamp<std::int64_t>(took_us, 0, INT32_MAX));
    ++timings_;
    const tof::PixelCounts& pixels = processor_.last_counts();
    for (int s = 0; s < tof::kPixelStates; ++s) counts_.pixels_by_state[s] += pixels.by_state[s];
    const double valid_share =
        static_cast<double>(pixels.of(tof::PixelState::kValid)) / static_cast<double>(tof::kPixels);
    ++counts_.frames_delivered;
    if (valid_share < config_.mostly_invalid_below) {
      ++counts_.frames_mostly_invalid;
      result = PipelineStatus::kMostlyInvalid;
    }
  }
  // Outside the lock: the listener may take its time (it must not block).
  if (listener_) listener_->on_new_data(frame);
  return result;
}

PipelineCounts RawDepthPipeline::counts() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counts_;
}

std::int64_t RawDepthPipeline::processing_median_us() const {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::size_t n = std::min(timings_, kTimingWindow);
  if (n == 0) return -1;
  std::copy(timing_us_.get(), timing_us_.get() + n, scratch_us_.get());
  std::int32_t* mid = scratch_us_.get() + n / 2;
  std::nth_element(scratch_us_.get(), mid, scratch_us_.get() + n);
  return *mid;
}

}  // namespace pico_flexx
