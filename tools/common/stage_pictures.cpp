#include "stage_pictures.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "depth_picture.hpp"
#include "estimator/pixel_scale.hpp"

namespace tools {
namespace {

constexpr Rgb kOverlayColour{60, 255, 60};

struct Stage {
  const char* suffix;
  const char* title;
  std::uint8_t flag;
  Rgb colour;
};

constexpr Stage kStages[] = {
    {"a_cloud", "A CLOUD", estimator::kFlagValid, {200, 200, 200}},
    {"b_plane", "B PLANE INLIERS", estimator::kFlagPlane, {60, 190, 70}},
    {"c_gap", "C GAP DISTANCE", estimator::kFlagGap, {240, 200, 40}},
    {"d_cross", "D CROSS POINT", estimator::kFlagCrossX | estimator::kFlagCrossY, {40, 180, 200}},
    {"e_side", "E SIDE WIDTH", estimator::kFlagSide, {230, 120, 30}},
    {"f_line", "F LINE AND ENDS", estimator::kFlagLine, {220, 40, 40}},
};

// One stage: its pixels in colour, every other pixel the camera gave grey
// by range (so a frame the detector gave up on early still shows).
Image stage_image(const hal::DepthFrame& frame, const estimator::Workspace& ws, const Stage& s) {
  const int w = static_cast<int>(frame.width), h = static_cast<int>(frame.height);
  Image img(w, h);
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      const std::size_t i = static_cast<std::size_t>(r * w + c);
      if (!(ws.flags[i] & estimator::kFlagValid) && !hal::is_valid(frame.points[i])) continue;
      const std::uint8_t g = static_cast<std::uint8_t>(
          std::clamp(255.0f - 120.0f * frame.points[i].z_m, 40.0f, 200.0f) / 3.0f);
      img.set(c, r, (ws.flags[i] & s.flag) ? s.colour : Rgb{g, g, g});
    }
  }
  return img.scaled(kPictureScale);
}

using Projection = std::function<bool(const Eigen::Vector3d&, Eigen::Vector2d*)>;

// A label in the 5x7 font at scale 2 on a black box, so it reads over any
// colour; moved inside the picture when (x, y) would cut it off.
void draw_label(Image* img, int x, int y, const std::string& text, Rgb colour) {
  constexpr int kScale = 2, kPad = 2;
  const int w = 6 * kScale * static_cast<int>(text.size()), h = 7 * kScale;
  x = std::clamp(x, kPad, std::max(kPad, img->width() - w - kPad));
  y = std::clamp(y, kPad, std::max(kPad, img->height() - h - kPad));
  img->rect(x - kPad, y - kPad, x + w + kPad - 1, y + h + kPad - 1, {0, 0, 0});
  img->text(x, y, text, colour, kScale);
}

// The refused line's visible extent, outlined in black so it shows on the
// depth colours too, with its verdict and search beside its middle. A line
// refused before it had a centre line has no place: its label goes under
// the picture's title instead.
void draw_refused_line(Image* img, const Projection& project,
                       const estimator::LineTraceEntry& line) {
  const std::string label =
      std::string(to_string(line.verdict)) + " S" + std::to_string(line.search);
  Eigen::Vector2d middle_px;
  if (!line.has_center_line || !project(line.middle_cam.cast<double>(), &middle_px)) {
    draw_label(img, 4, 26, "BEST LINE " + label, kRefusedLineColour);
    return;
  }
  const Eigen::Vector3d half = 0.5 * line.visible_length_m * line.axis_cam.cast<double>();
  const Eigen::Vector3d middle = line.middle_cam.cast<double>();
  draw_segment(img, project, middle - half, middle + half, {0, 0, 0}, 7);
  draw_segment(img, project, middle - half, middle + half, kRefusedLineColour, 3);
  // Beside the line, not on it: off the middle, across the line's
  // direction in the picture.
  Eigen::Vector2d end_px;
  Eigen::Vector2d across(1.0, 0.0);
  if (project(middle + half, &end_px) && (end_px - middle_px).norm() > 1e-6) {
    const Eigen::Vector2d along = (end_px - middle_px).normalized();
    across = Eigen::Vector2d(-along.y(), along.x());
    if (across.x() < 0.0) across = -across;  // the text runs right: start right of the line
  }
  const Eigen::Vector2d at =
      (middle_px + Eigen::Vector2d(0.5, 0.5)) * kPictureScale + 20.0 * across;
  // Below the line the label hangs from that point; above it, stands on it.
  const int y = static_cast<int>(at.y()) - (across.y() < 0.0 ? 14 : 0);
  draw_label(img, static_cast<int>(at.x()), y, label, kRefusedLineColour);
}

}  // namespace

std::vector<StagePicture> draw_stage_pictures(const hal::DepthFrame& frame,
                                              const estimator::OrganizedCloud& cloud,
                                              const estimator::HandrailDetector& det,
                                              const estimator::HandrailDetection& d,
                                              const std::vector<CameraSegment>& overlay,
                                              const estimator::LineTraceEntry* refused_line) {
  const estimator::Workspace& ws = det.workspace();
  const estimator::PixelScale scale = estimator::estimate_pixel_scale(cloud, ws.sample);
  auto project = [&](const Eigen::Vector3d& p, Eigen::Vector2d* px) {
    if (!scale.ok || p.z() <= 1e-6) return false;
    *px = {scale.cx_px + scale.fx_px * p.x() / p.z(), scale.cy_px + scale.fy_px * p.y() / p.z()};
    return true;
  };
  const bool found = d.status == estimator::DetectStatus::kFound;
  std::vector<StagePicture> out;
  out.reserve(std::size(kStages) + 1);
  for (const Stage& s : kStages) {
    Image big = stage_image(frame, ws, s);
    if (s.flag == estimator::kFlagLine) {
      for (const CameraSegment& seg : overlay) {
        draw_segment(&big, project, seg.first, seg.second, kOverlayColour, 2);
      }
      for (int e = 0; found && e < 2; ++e) {
        Eigen::Vector2d px;
        if (project(d.ends_cam[e].cast<double>(), &px)) {
          big.disc((px.x() + 0.5) * kPictureScale, (px.y() + 0.5) * kPictureScale, 5,
                   d.end_seen[e] ? Rgb{255, 0, 255} : Rgb{120, 120, 255});
        }
      }
      if (refused_line) draw_refused_line(&big, project, *refused_line);
    }
    big.text(4, 4, s.title, {255, 255, 255}, 2);
    out.push_back({s.suffix, std::move(big)});
  }
  // The final pose over the depth image: centre line, centre, target offset.
  Image pose = depth_picture(frame);
  for (const CameraSegment& seg : overlay) {
    draw_segment(&pose, project, seg.first, seg.second, kOverlayColour, 2);
  }
  // Under the pose: when the refused line is the found bar seen again from
  // another mount, the answer stays in view.
  if (refused_line) draw_refused_line(&pose, project, *refused_line);
  if (found) {
    draw_segment(&pose, project, d.ends_cam[0].cast<double>(), d.ends_cam[1].cast<double>(),
                 {255, 255, 255}, 3);
    draw_segment(&pose, project, d.p_cam_center.cast<double>(),
                 (d.p_cam_center + 0.1f * d.normal()).cast<double>(), {255, 0, 0}, 2);
    draw_segment(&pose, project, d.p_cam_center.cast<double>(),
                 (d.p_cam_center + 0.1f * d.R_cam_handrail.col(1)).cast<double>(), {0, 255, 0}, 2);
    pose.text(4, 4, std::string("POSE ") + to_string(d.state), {255, 255, 255}, 2);
  } else {
    pose.text(4, 4, std::string("NH ") + to_string(d.status), {255, 255, 255}, 2);
  }
  out.push_back({"g_pose", std::move(pose)});
  return out;
}

Image contact_sheet(const std::vector<StagePicture>& pictures, int columns,
                    const std::string& caption) {
  constexpr int kGap = 6, kLine = 20;  // a 5x7 font at scale 2, and space
  std::vector<std::string> lines;
  for (std::size_t start = 0; start <= caption.size();) {
    const std::size_t end = std::min(caption.find('\n', start), caption.size());
    lines.push_back(caption.substr(start, end - start));
    start = end + 1;
  }
  const int caption_h = 8 + kLine * static_cast<int>(lines.size());
  int cell_w = 0, cell_h = 0;
  for (const StagePicture& p : pictures) {
    cell_w = std::max(cell_w, p.image.width());
    cell_h = std::max(cell_h, p.image.height());
  }
  columns = std::max(1, columns);
  const int n = static_cast<int>(pictures.size());
  const int rows = (n + columns - 1) / columns;
  Image sheet(columns * cell_w + (columns + 1) * kGap, caption_h + rows * (cell_h + kGap) + kGap,
              {25, 25, 25});
  for (std::size_t k = 0; k < lines.size(); ++k) {
    sheet.text(kGap, 8 + kLine * static_cast<int>(k), lines[k], {255, 255, 255}, 2);
  }
  for (int k = 0; k < n; ++k) {
    const Image& img = pictures[static_cast<std::size_t>(k)].image;
    const int x0 = kGap + (k % columns) * (cell_w + kGap);
    const int y0 = caption_h + (k / columns) * (cell_h + kGap);
    for (int y = 0; y < img.height(); ++y)
      for (int x = 0; x < img.width(); ++x) sheet.set(x0 + x, y0 + y, img.get(x, y));
  }
  return sheet;
}

}  // namespace tools
