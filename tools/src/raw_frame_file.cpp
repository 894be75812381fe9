#include "raw_frame_file.hpp"

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>

namespace tools {

namespace {

constexpr char kMagic[8] = {'H', 'R', 'P', 'R', 'A', 'W', '1', '\n'};
constexpr std::size_t kHeaderBytes = 48;

// The header fields in file order, little-endian whatever the host.
void put32(unsigned char* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}
void put64(unsigned char* p, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}
std::uint32_t get32(const unsigned char* p) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(p[i]) << (8 * i);
  return v;
}
std::uint64_t get64(const unsigned char* p) {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(p[i]) << (8 * i);
  return v;
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

}  // namespace

bool write_raw_frame(const std::string& path, const tof::RawFrame& frame, std::string* error) {
  const int images = tof::raw_image_count(frame.mode);
  unsigned char header[kHeaderBytes] = {};
  std::memcpy(header, kMagic, sizeof kMagic);
  put32(header + 8, tof::kWidthPx);
  put32(header + 12, tof::kHeightPx);
  put32(header + 16, static_cast<std::uint32_t>(images));
  put32(header + 20, frame.exposure_us);
  put64(header + 24, frame.frame_id);
  put64(header + 32, static_cast<std::uint64_t>(frame.capture_time_us));
  std::uint32_t temperature_bits = 0;
  std::memcpy(&temperature_bits, &frame.sensor_temperature_c, 4);
  put32(header + 40, temperature_bits);
  std::unique_ptr<std::FILE, FileCloser> f(std::fopen(path.c_str(), "wb"));
  if (!f) {
    *error = path + ": cannot write: " + std::strerror(errno);
    return false;
  }
  bool ok = std::fwrite(header, 1, kHeaderBytes, f.get()) == kHeaderBytes;
  unsigned char row[2 * tof::kWidthPx];
  for (int k = 0; ok && k < images; ++k) {
    const std::uint16_t* samples = frame.image(k);
    for (std::uint32_t y = 0; ok && y < tof::kHeightPx; ++y) {
      for (std::uint32_t x = 0; x < tof::kWidthPx; ++x) {
        const std::uint16_t v = samples[y * tof::kWidthPx + x];
        row[2 * x] = static_cast<unsigned char>(v);
        row[2 * x + 1] = static_cast<unsigned char>(v >> 8);
      }
      ok = std::fwrite(row, 1, sizeof row, f.get()) == sizeof row;
    }
  }
  if (!ok || std::fclose(f.release()) != 0) {
    *error = path + ": write failed";
    return false;
  }
  return true;
}

bool read_raw_frame(const std::string& path, tof::RawFrame* frame, std::string* error) {
  std::unique_ptr<std::FILE, FileCloser> f(std::fopen(path.c_str(), "rb"));
  if (!f) {
    *error = path + ": cannot read: " + std::strerror(errno);
    return false;
  }
  unsigned char header[kHeaderBytes];
  if (std::fread(header, 1, kHeaderBytes, f.get()) != kHeaderBytes ||
      std::memcmp(header, kMagic, sizeof kMagic) != 0) {
    *error = path + ": not a raw frame file (no HRPRAW1 header)";
    return false;
  }
  if (get32(header + 8) != tof::kWidthPx || get32(header + 12) != tof::kHeightPx) {
    *error = path + ": the size is not 224 x 171";
    return false;
  }
  const std::uint32_t images = get32(header + 16);
  if (images != 9 && images != 5) {
    *error = path + ": " + std::to_string(images) + " raw images (9 or 5)";
    return false;
  }
  frame->mode = images == 9 ? tof::Mode::kMode9 : tof::Mode::kMode5;
  frame->exposure_us = get32(header + 20);
  frame->frame_id = get64(header + 24);
  frame->capture_time_us = static_cast<std::int64_t>(get64(header + 32));
  const std::uint32_t temperature_bits = get32(header + 40);
  std::memcpy(&frame->sensor_temperature_c, &temperature_bits, 4);
  unsigned char row[2 * tof::kWidthPx];
  for (std::uint32_t k = 0; k < images; ++k) {
    std::uint16_t* samples = frame->image(static_cast<int>(k));
    for (std::uint32_t y = 0; y < tof::kHeightPx; ++y) {
      if (std::fread(row, 1, sizeof row, f.get()) != sizeof row) {
        *error = path + ": truncated in image " + std::to_string(k);
        return false;
      }
      for (std::uint32_t x = 0; x < tof::kWidthPx; ++x) {
        const std::uint16_t v = static_cast<std::uint16_t>(row[2 * x] | (row[2 * x + 1] << 8));
        if (v > tof::kMaxSampleDn) {
          *error = path + ": image " + std::to_string(k) + " row " + std::to_string(y) +
                   ": sample " + std::to_string(v) + " above 4095";
          return false;
        }
        samples[y * tof::kWidthPx + x] = v;
      }
    }
  }
  if (std::fgetc(f.get()) != EOF) {
    *error = path + ": bytes after the last image";
    return false;
  }
  return true;
}

}  // namespace tools
