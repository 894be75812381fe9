#pragma once
// hreval's worst frame of a scenario: the proposed method's worst failure,
// kept (a copy of the frame) to be drawn once the scenario has run.
#include <cstdint>
#include <string>
#include <tuple>
#include <vector>

#include "common/stage_pictures.hpp"
#include "estimator/handrail_detector.hpp"
#include "hal/depth_frame.hpp"
#include "sim_hal/ground_truth.hpp"

namespace tools {

// A false detection is the worst kind, since the arm would go for it, and
// the more line inliers the worse; then a missed target in reach, the more
// of it visible and the nearer the worse; then a missed target out of
// reach.
class WorstFrame {
 public:
  // A failed frame: `is_false` for a false detection, otherwise a missed
  // target (`target`, `reach_target` as hreval's tallies take them).
  void consider(const hal::DepthFrame& frame, const sim_hal::FrameTruth& truth,
                const estimator::HandrailDetection& d, bool is_false, int target, int reach_target);
  bool any() const { return std::get<0>(rank_) >= 0; }
  std::uint64_t frame_index() const { return frame_index_; }
  const std::string& reason() const { return reason_; }

  // Runs the detector on the frame again, its workspace showing the search
  // that gave the result, and writes the stage pictures as one sheet with
  // the true centre lines in green (picture_path), and the detection with
  // every line the frame tested and its verdict (lines_path: JSON, the
  // fields of hrdetect --lines). The detector draws each frame's random
  // streams from its frame id, so the result is the one scored.
  bool write_picture(const std::string& picture_path, const std::string& lines_path,
                     const std::string& scenario, estimator::DetectorConfig cfg,
                     std::string* error) const;

 private:
  std::tuple<int, double, double> rank_{-1, 0.0, 0.0};
  std::uint64_t frame_index_ = 0;
  std::string reason_;
  std::vector<hal::DepthPoint> points_;
  hal::DepthFrame view_;
  std::vector<CameraSegment> truth_;
};

}  // namespace tools
