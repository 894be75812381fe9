#include "png_image.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "font5x7.hpp"

namespace tools {

Image::Image(int width, int height, Rgb fill)
    : width_(width), height_(height), pixels_(static_cast<std::size_t>(width * height), fill) {}

void Image::set(int x, int y, Rgb c) {
  if (x >= 0 && y >= 0 && x < width_ && y < height_)
    pixels_[static_cast<std::size_t>(y * width_ + x)] = c;
}

// Cuts the segment to the picture (grown by `margin`), Liang-Barsky: an end
// projected from a point just in front of the camera lies millions of
// pixels away, and stepping there pixel by pixel took seconds per line.
// False when nothing of it is inside.
bool Image::clip(double* x0, double* y0, double* x1, double* y1, double margin) const {
  const double dx = *x1 - *x0, dy = *y1 - *y0;
  double t0 = 0.0, t1 = 1.0;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {*x0 + margin, width_ - 1 + margin - *x0, *y0 + margin,
                       height_ - 1 + margin - *y0};
  for (int k = 0; k < 4; ++k) {
    if (!std::isfinite(p[k]) || !std::isfinite(q[k])) return false;
    if (p[k] == 0.0) {
      if (q[k] < 0.0) return false;
      continue;
    }
    const double r = q[k] / p[k];
    if (p[k] < 0.0) {
      t0 = std::max(t0, r);
    } else {
      t1 = std::min(t1, r);
    }
    if (t0 > t1) return false;
  }
  const double ax = *x0, ay = *y0;
  *x0 = ax + t0 * dx;
  *y0 = ay + t0 * dy;
  *x1 = ax + t1 * dx;
  *y1 = ay + t1 * dy;
  return true;
}

void Image::line(double x0, double y0, double x1, double y1, Rgb c, int thickness) {
  if (!clip(&x0, &y0, &x1, &y1, thickness)) return;
  const double len = std::hypot(x1 - x0, y1 - y0);
  const int steps = std::max(1, static_cast<int>(std::ceil(len * 2.0)));
  for (int k = 0; k <= steps; ++k) {
    const double f = static_cast<double>(k) / steps;
    const int x = static_cast<int>(std::lround(x0 + f * (x1 - x0)));
    const int y = static_cast<int>(std::lround(y0 + f * (y1 - y0)));
    for (int dy = -(thickness / 2); dy <= thickness / 2; ++dy)
      for (int dx = -(thickness / 2); dx <= thickness / 2; ++dx) set(x + dx, y + dy, c);
  }
}

void Image::rect(int x0, int y0, int x1, int y1, Rgb c) {
  for (int y = std::min(y0, y1); y <= std::max(y0, y1); ++y)
    for (int x = std::min(x0, x1); x <= std::max(x0, x1); ++x) set(x, y, c);
}

void Image::disc(double cx, double cy, double radius, Rgb c) {
  const int r = static_cast<int>(std::ceil(radius));
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx)
      if (dx * dx + dy * dy <= radius * radius)
        set(static_cast<int>(std::lround(cx)) + dx, static_cast<int>(std::lround(cy)) + dy, c);
}

void Image::text(int x, int y, const std::string& s, Rgb c, int scale) {
  int pen = x;
  for (char ch : s) {
    const std::uint8_t* rows = font5x7_rows(ch);
    for (int row = 0; row < 7; ++row)
      for (int col = 0; col < 5; ++col)
        if (rows[row] & (0x10u >> col))
          rect(pen + col * scale, y + row * scale, pen + col * scale + scale - 1,
               y + row * scale + scale - 1, c);
    pen += 6 * scale;
  }
}

Image Image::scaled(int factor) const {
  Image out(width_ * factor, height_ * factor);
  for (int y = 0; y < out.height_; ++y)
    for (int x = 0; x < out.width_; ++x) out.set(x, y, get(x / factor, y / factor));
  return out;
}

namespace {

// libpng reports errors by longjmp; this function keeps no C++ object with a
// destructor alive across its setjmp, so nothing can be skipped or clobbered.
bool write_png_rows(FILE* f, int width, int height, const Rgb* pixels) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < height; ++y) {
    png_write_row(
        png, reinterpret_cast<png_const_bytep>(pixels + static_cast<std::ptrdiff_t>(y) * width));
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

bool Image::write_png(const std::string& path, std::string* error) const {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) {
    *error = path + ": cannot create the PNG file";
    return false;
  }
  const bool ok = write_png_rows(f, width_, height_, pixels_.data());
  if (std::fclose(f) != 0 || !ok) {
    *error = path + ": writing the PNG failed (disk full?)";
    return false;
  }
  return true;
}

Rgb false_colour(double t) {
  t = std::clamp(t, 0.0, 1.0);
  // A short "turbo"-like ramp: red, yellow, green, cyan, blue.
  static const Rgb stops[] = {
      {200, 30, 30}, {240, 200, 40}, {60, 190, 70}, {40, 180, 200}, {40, 60, 190}};
  const double x = t * 4.0;
  const int k = std::min(3, static_cast<int>(x));
  const double f = x - k;
  auto mix = [f](std::uint8_t a, std::uint8_t b) {
    return static_cast<std::uint8_t>(a + f * (b - a));
  };
  return {mix(stops[k].r, stops[k + 1].r), mix(stops[k].g, stops[k + 1].g),
          mix(stops[k].b, stops[k + 1].b)};
}

}  // namespace tools
