#include "dynamic_chart.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "png_image.hpp"

namespace tools {
namespace {

constexpr int kWidth = 1100, kPanelHeight = 330, kLeft = 90, kRight = 20, kTop = 40;
constexpr Rgb kWhite{255, 255, 255}, kBlack{0, 0, 0}, kGrid{220, 220, 220};
constexpr Rgb kEstimate{30, 90, 220}, kGp{220, 60, 40};

struct Axis {
  double lo = 0.0, hi = 1.0;
  int p0 = 0, p1 = 1;  // pixels of lo and hi
  double map(double v) const { return p0 + (v - lo) / (hi - lo) * (p1 - p0); }
};

void panel(Image* img, int top, const char* name, double t_end,
           const std::vector<TrackSample>& track, const std::vector<FixSample>& gp, bool x) {
  double lo = 1e9, hi = -1e9;
  for (const TrackSample& s : track) {
    const double a = x ? s.true_x : s.true_y, b = x ? s.est_x : s.est_y;
    lo = std::min({lo, a, b});
    hi = std::max({hi, a, b});
  }
  const double pad = std::max(0.01, 0.08 * (hi - lo));
  lo -= pad;
  hi += pad;
  const Axis tx{0.0, t_end, kLeft, kWidth - kRight};
  const Axis vy{lo, hi, top + kPanelHeight - 30, top + 10};
  // Grid every 10 s and at five levels, labelled.
  for (double t = 0.0; t <= t_end + 1e-9; t += 10.0) {
    img->line(tx.map(t), vy.p1, tx.map(t), vy.p0, kGrid);
    char label[16];
    std::snprintf(label, sizeof label, "%.0f", t);
    img->text(static_cast<int>(tx.map(t)) - 6, vy.p0 + 6, label, kBlack, 2);
  }
  for (int k = 0; k <= 4; ++k) {
    const double v = lo + (hi - lo) * k / 4.0;
    img->line(tx.p0, vy.map(v), tx.p1, vy.map(v), kGrid);
    char label[16];
    std::snprintf(label, sizeof label, "%.2f", v);
    img->text(8, static_cast<int>(vy.map(v)) - 7, label, kBlack, 2);
  }
  img->text(kLeft + 8, top + 14, name, kBlack, 2);
  for (std::size_t k = 1; k < track.size(); ++k) {
    const TrackSample &a = track[k - 1], &b = track[k];
    img->line(tx.map(a.t_s), vy.map(x ? a.true_x : a.true_y), tx.map(b.t_s),
              vy.map(x ? b.true_x : b.true_y), kBlack, 3);
    img->line(tx.map(a.t_s), vy.map(x ? a.est_x : a.est_y), tx.map(b.t_s),
              vy.map(x ? b.est_x : b.est_y), kEstimate, 2);
  }
  for (const FixSample& f : gp) {
    const double v = x ? f.x : f.y;
    if (v >= lo && v <= hi) img->disc(tx.map(f.t_s), vy.map(v), 3.0, kGp);
  }
}

}  // namespace

bool write_track_chart(const std::string& path, const std::string& title,
                       const std::vector<TrackSample>& track, const std::vector<FixSample>& gp,
                       std::string* error) {
  if (track.size() < 2) {
    *error = "nothing to plot";
    return false;
  }
  Image img(kWidth, kTop + 2 * kPanelHeight + 40, kWhite);
  img.text(kLeft, 10, title, kBlack, 2);
  const double t_end = std::ceil(track.back().t_s / 10.0) * 10.0;
  panel(&img, kTop, "X (M, OUT FROM THE WALL)", t_end, track, gp, true);
  panel(&img, kTop + kPanelHeight, "Y (M, ALONG THE WALL)", t_end, track, gp, false);
  const int legend_y = kTop + 2 * kPanelHeight + 12;
  img.line(kLeft, legend_y + 7, kLeft + 40, legend_y + 7, kBlack, 3);
  img.text(kLeft + 50, legend_y, "TRUE", kBlack, 2);
  img.line(kLeft + 160, legend_y + 7, kLeft + 200, legend_y + 7, kEstimate, 2);
  img.text(kLeft + 210, legend_y, "FILTER", kBlack, 2);
  img.disc(kLeft + 340, legend_y + 7, 3.0, kGp);
  img.text(kLeft + 355, legend_y, "GP LOCALIZER", kBlack, 2);
  img.text(kWidth - 160, legend_y, "TIME (S)", kBlack, 2);
  return img.write_png(path, error);
}

}  // namespace tools
