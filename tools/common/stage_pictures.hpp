#pragma once
// Pictures of the detector's stages on one frame (the paper's Figure 5 (a)
// to (f), and the pose), for hrdetect's --debug-png and hreval's picture of
// a scenario's worst frame.
#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "estimator/handrail_detector.hpp"
#include "estimator/line_trace.hpp"
#include "hal/depth_frame.hpp"
#include "png_image.hpp"

namespace tools {

struct StagePicture {
  const char* suffix;  // a_cloud ... f_line, g_pose: the file name's stage part
  Image image;         // kPictureScale times the frame's size
};

// A segment in the camera frame, drawn over the line and pose pictures
// (hreval: the true handrail's centre line).
using CameraSegment = std::pair<Eigen::Vector3d, Eigen::Vector3d>;

// The seven pictures of the frame `det` last processed (`d` its result):
// per stage, the pixels the stage kept in colour over the depth image in
// grey; the line's ends (magenta when seen); then the pose over the depth
// image. The workspace shows the last mount searched unless the detector was
// configured with workspace_shows_result. `overlay` is drawn in green.
// `refused_line` (a line from the detector's trace that it refused, or
// null) is drawn in orange over the line and pose pictures with its
// verdict and search beside it ("NOT_ON_TRACK S2"): a refusal by a search
// the workspace does not show.
std::vector<StagePicture> draw_stage_pictures(
    const hal::DepthFrame& frame, const estimator::OrganizedCloud& cloud,
    const estimator::HandrailDetector& det, const estimator::HandrailDetection& d,
    const std::vector<CameraSegment>& overlay = {},
    const estimator::LineTraceEntry* refused_line = nullptr);

// The colour refused_line is drawn in: no depth colour, stage or overlay
// has it, so it can be told (and counted) in any picture.
constexpr Rgb kRefusedLineColour{255, 140, 0};

// The pictures side by side, `columns` to a row, under a caption (one
// line of text per '\n'-separated part).
Image contact_sheet(const std::vector<StagePicture>& pictures, int columns,
                    const std::string& caption);

}  // namespace tools
