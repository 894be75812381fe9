#include "worst_frame.hpp"

#include <algorithm>
#include <cctype>

#include <fstream>

#include "common/detection_json.hpp"
#include "common/frame_convert.hpp"

namespace tools {
namespace {

std::string why(const estimator::HandrailDetection& d, bool is_false) {
  if (is_false) {
    return std::string("FALSE (") + estimator::to_string(d.state) + ", " +
           std::to_string(d.inliers) + " inliers)";
  }
  std::string s = std::string("missed, ") + estimator::to_string(d.status);
  if (d.status == estimator::DetectStatus::kNoLine) {
    s += std::string(" (") + estimator::to_string(d.counts.first_rejection) + ")";
  }
  return s;
}

}  // namespace

void WorstFrame::consider(const hal::DepthFrame& frame, const sim_hal::FrameTruth& truth,
                          const estimator::HandrailDetection& d, bool is_false, int target,
                          int reach_target) {
  std::tuple<int, double, double> rank;
  if (is_false) {
    rank = {3, d.inliers, 0.0};
  } else {
    const int t = reach_target >= 0 ? reach_target : target;
    const sim_hal::HandrailTruth& h = truth.handrails[static_cast<std::size_t>(t)];
    rank = {reach_target >= 0 ? 2 : 1, h.visible_fraction, -h.visible_center_cam.norm()};
  }
  if (rank <= rank_) return;
  rank_ = rank;
  frame_index_ = truth.frame;
  reason_ = why(d, is_false);
  const std::size_t n = static_cast<std::size_t>(frame.width) * frame.height;
  points_.assign(frame.points, frame.points + n);
  view_ = frame;
  view_.points = points_.data();
  truth_.clear();
  for (const sim_hal::HandrailTruth& h : truth.handrails) {
    truth_.emplace_back(h.ends_cam[0], h.ends_cam[1]);
  }
}

bool WorstFrame::write_picture(const std::string& picture_path, const std::string& lines_path,
                               const std::string& scenario, estimator::DetectorConfig cfg,
                               std::string* error) const {
  cfg.workspace_shows_result = true;
  estimator::HandrailDetector det(cfg);
  det.set_line_trace(true);
  std::vector<estimator::CloudPoint> buffer;
  const estimator::OrganizedCloud cloud = to_estimator_cloud(view_, &buffer);
  const estimator::HandrailDetection d = det.detect(cloud, estimator::Method::kProposed);
  std::ofstream lines(lines_path);
  lines << with_line_trace(
               detection_to_json(scenario + " frame " + std::to_string(frame_index_), d),
               det.last_line_trace())
        << "\n";
  if (!lines.flush()) {
    *error = lines_path + ": cannot be written";
    return false;
  }
  std::string caption = scenario + " FRAME " + std::to_string(frame_index_) + ": " + reason_;
  std::transform(caption.begin(), caption.end(), caption.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  caption +=
      "\nGREEN: TRUE CENTRE LINES. WHITE: THE DETECTED ONE, RED ITS WALL NORMAL. DOTS: ITS "
      "ENDS (MAGENTA: SEEN)";
  const std::vector<StagePicture> stages = draw_stage_pictures(view_, cloud, det, d, truth_);
  return contact_sheet(stages, 4, caption).write_png(picture_path, error);
}

}  // namespace tools
