#pragma once
// RGB images for debug pictures and charts, written with libpng.
#include <cstdint>
#include <string>
#include <vector>

namespace tools {

struct Rgb {
  std::uint8_t r, g, b;
};

class Image {
 public:
  Image(int width, int height, Rgb fill = {0, 0, 0});
  int width() const { return width_; }
  int height() const { return height_; }
  void set(int x, int y, Rgb c);
  Rgb get(int x, int y) const { return pixels_[static_cast<std::size_t>(y * width_ + x)]; }
  // Only the part inside the picture is drawn, however far the ends lie.
  void line(double x0, double y0, double x1, double y1, Rgb c, int thickness = 1);
  void rect(int x0, int y0, int x1, int y1, Rgb c);  // filled, inclusive
  void disc(double x, double y, double radius, Rgb c);
  // Text in a built-in 5x7 font (ASCII 32..126), `scale` pixels per dot.
  void text(int x, int y, const std::string& s, Rgb c, int scale = 1);
  // Nearest-neighbour enlargement, for small depth images.
  Image scaled(int factor) const;
  bool write_png(const std::string& path, std::string* error) const;

 private:
  bool clip(double* x0, double* y0, double* x1, double* y1, double margin) const;
  int width_, height_;
  std::vector<Rgb> pixels_;
};

// Maps t in [0, 1] to a perceptually ordered colour (near = warm, far = cool).
Rgb false_colour(double t);

}  // namespace tools
