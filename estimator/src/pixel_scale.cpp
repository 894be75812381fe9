#include "estimator/pixel_scale.hpp"

namespace estimator {
namespace {
// Least squares for pixel = c + f * ratio.
bool fit_axis(double n, double s_r, double s_p, double s_rr, double s_rp, float* f, float* c) {
  const double det = n * s_rr - s_r * s_r;
  if (n < 10 || det <= 1e-12) return false;
  const double slope = (n * s_rp - s_r * s_p) / det;
  *f = static_cast<float>(slope);
  *c = static_cast<float>((s_p - slope * s_r) / n);
  return slope > 0.0;
}
}  // namespace

PixelScale estimate_pixel_scale(const OrganizedCloud& cloud, const IndexList& valid) {
  PixelScale scale;
  // A few thousand points pin two parameters down far below a pixel.
  const std::size_t step = valid.size() > 4000 ? valid.size() / 4000 : 1;
  double n = 0, sx = 0, su = 0, sxx = 0, sxu = 0, sy = 0, sv = 0, syy = 0, syv = 0;
  for (std::size_t k = 0; k < valid.size(); k += step) {
    const std::int32_t i = valid[k];
    const CloudPoint& p = cloud.points[i];
    const double rx = p.x_m / p.z_m, ry = p.y_m / p.z_m;
    const double u = i % static_cast<std::int32_t>(cloud.width);
    const double v = i / static_cast<std::int32_t>(cloud.width);
    n += 1;
    sx += rx;
    su += u;
    sxx += rx * rx;
    sxu += rx * u;
    sy += ry;
    sv += v;
    syy += ry * ry;
    syv += ry * v;
  }
  scale.ok = fit_axis(n, sx, su, sxx, sxu, &scale.fx_px, &scale.cx_px) &&
             fit_axis(n, sy, sv, syy, syv, &scale.fy_px, &scale.cy_px);
  return scale;
}

}  // namespace estimator
