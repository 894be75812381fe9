#include "eval_chart.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "png_image.hpp"

namespace tools {
namespace {

struct Metric {
  const char* label;
  const Stats Tally::*stats;
};

const Rgb kSeriesColours[] = {{150, 150, 150}, {40, 110, 200}, {220, 120, 40}};

// One panel: groups of bars (one per series) for each metric.
void draw_panel(Image* img, int x0, int y0, int w, int h, const char* unit, const Metric* metrics,
                int n_metrics, const std::vector<ChartSeries>& series) {
  double top = 1e-9;
  for (int m = 0; m < n_metrics; ++m)
    for (const ChartSeries& s : series) {
      const Stats& st = s.tally->*metrics[m].stats;
      if (!st.values.empty()) top = std::max(top, std::fabs(st.mean()) + st.stddev());
    }
  // A round axis top: 1, 2 or 5 times a power of ten.
  const double p = std::pow(10.0, std::floor(std::log10(top)));
  const double nice = top <= p ? p : top <= 2 * p ? 2 * p : top <= 5 * p ? 5 * p : 10 * p;
  const Rgb axis{60, 60, 60};
  img->line(x0, y0, x0, y0 + h, axis);
  img->line(x0, y0 + h, x0 + w, y0 + h, axis);
  for (int k = 0; k <= 4; ++k) {
    const int y = y0 + h - k * h / 4;
    img->line(x0 - 4, y, x0, y, axis);
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", nice * k / 4);
    img->text(x0 - 8 - 6 * static_cast<int>(std::string(buf).size()), y - 3, buf, axis);
  }
  img->text(x0 - 40, y0 - 16, unit, axis);
  const int group_w = w / n_metrics;
  const int bar_w = std::max(6, (group_w - 20) / static_cast<int>(series.size()));
  for (int m = 0; m < n_metrics; ++m) {
    const int gx = x0 + m * group_w + 10;
    for (std::size_t s = 0; s < series.size(); ++s) {
      const Stats& st = series[s].tally->*metrics[m].stats;
      if (st.values.empty()) continue;
      // Magnitude of the mean error, with the spread as a whisker.
      const double mean = std::fabs(st.mean()), sd = st.stddev();
      const int bx = gx + static_cast<int>(s) * bar_w;
      const int by = y0 + h - static_cast<int>(std::min(1.0, mean / nice) * h);
      img->rect(bx, by, bx + bar_w - 3, y0 + h - 1, kSeriesColours[s % 3]);
      const int cx = bx + (bar_w - 3) / 2;
      const int wy = y0 + h - static_cast<int>(std::min(1.0, (mean + sd) / nice) * h);
      img->line(cx, by, cx, wy, {0, 0, 0});
      img->line(cx - 3, wy, cx + 3, wy, {0, 0, 0});
    }
    img->text(gx, y0 + h + 8, metrics[m].label, axis);
  }
}

}  // namespace

bool write_error_chart(const std::string& path, const std::string& title,
                       const std::vector<ChartSeries>& series, std::string* error) {
  Image img(900, 420, {255, 255, 255});
  img.text(20, 12, title, {0, 0, 0}, 2);
  for (std::size_t s = 0; s < series.size(); ++s) {
    const int x = 620 + static_cast<int>(s) * 130;
    img.rect(x, 14, x + 14, 26, kSeriesColours[s % 3]);
    img.text(x + 20, 16, series[s].name, {0, 0, 0});
  }
  const Metric position[] = {
      {"X", &Tally::x}, {"Y", &Tally::y}, {"Z", &Tally::z}, {"BEAM", &Tally::beam}};
  const Metric rotation[] = {
      {"ROLL", &Tally::roll}, {"PITCH", &Tally::pitch}, {"YAW", &Tally::yaw}};
  draw_panel(&img, 80, 70, 380, 290, "MM", position, 4, series);
  draw_panel(&img, 560, 70, 300, 290, "DEG", rotation, 3, series);
  img.text(20, 400, "BARS: ABSOLUTE MEAN ERROR. WHISKERS: + 1 STANDARD DEVIATION", {90, 90, 90});
  return img.write_png(path, error);
}

}  // namespace tools
