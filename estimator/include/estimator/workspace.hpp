#pragma once
// Every buffer the detector touches while it processes a frame, sized once
// from the largest frame. Nothing here grows after construction.
#include <cstddef>
#include <cstdint>
#include <memory>

namespace estimator {

// A list of pixel indices with a fixed capacity. push() refuses (returns
// false) rather than grow.
class IndexList {
 public:
  explicit IndexList(std::size_t capacity = 0) { reset_capacity(capacity); }
  void reset_capacity(std::size_t capacity) {
    data_.reset(capacity ? new std::int32_t[capacity] : nullptr);
    capacity_ = capacity;
    size_ = 0;
  }
  bool push(std::int32_t index) {
    if (size_ >= capacity_) return false;
    data_[size_++] = index;
    return true;
  }
  void clear() { size_ = 0; }
  void resize_down(std::size_t n) { size_ = n < size_ ? n : size_; }
  // For writers that fill begin()[0..n) directly; clamped to the capacity.
  void set_size(std::size_t n) { size_ = n < capacity_ ? n : capacity_; }
  std::size_t size() const { return size_; }
  std::size_t capacity() const { return capacity_; }
  bool empty() const { return size_ == 0; }
  std::int32_t operator[](std::size_t i) const { return data_[i]; }
  std::int32_t& operator[](std::size_t i) { return data_[i]; }
  std::int32_t* begin() { return data_.get(); }
  std::int32_t* end() { return data_.get() + size_; }
  const std::int32_t* begin() const { return data_.get(); }
  const std::int32_t* end() const { return data_.get() + size_; }

 private:
  std::unique_ptr<std::int32_t[]> data_;
  std::size_t capacity_ = 0;
  std::size_t size_ = 0;
};

// Per-pixel flags set by the stages (bit per stage), for debug images.
enum PixelFlag : std::uint8_t {
  kFlagValid = 1u << 0,
  kFlagPlane = 1u << 1,
  kFlagGap = 1u << 2,
  kFlagCrossX = 1u << 3,
  kFlagCrossY = 1u << 4,
  kFlagSide = 1u << 5,
  kFlagLine = 1u << 6,
  kFlagWall = 1u << 7,  // valid and not above the wall tolerance: what the cross test's probes seek
};

struct Workspace {
  explicit Workspace(std::size_t max_pixels);

  std::size_t max_pixels;
  std::unique_ptr<float[]> signed_distance_m;  // to the wall; -infinity where not kFlagValid
  // The gap distance pass against the dominant plane, kept for the searches
  // on other mounts (the same distances, shifted): the distances, and each
  // pixel's widening of the gap window (twice its bounded noise).
  std::unique_ptr<float[]> plane_distance_m;
  // The distances to a bar's own surface, where it is not the searched
  // wall (local_surface.hpp): swapped with signed_distance_m while the bar
  // is verified on it.
  std::unique_ptr<float[]> local_distance_m;
  std::unique_ptr<float[]> gap_widen_m;
  // 1 / z per pixel from the same pass (the cross test's probe offsets are
  // metres over depth): one stream of floats the searches read back in
  // ascending order, instead of a division and a load from the cloud's
  // larger points per pixel and search.
  std::unique_ptr<float[]> inverse_depth_per_m;
  std::unique_ptr<std::uint8_t[]> flags;  // PixelFlag bits
  std::unique_ptr<float[]> line_t_m;      // position along a line
  IndexList sample;  // valid pixels at a fixed stride, for the wall and the pixel scale
  IndexList gap;
  IndexList cross;
  IndexList side;
  IndexList line[2];
  IndexList scratch;                  // the line search's remaining points
  IndexList band;                     // raised pixels around a candidate line
  std::unique_ptr<float[]> values;    // per-point scratch for medians
  std::unique_ptr<float[]> wall_u_m;  // side points' coordinates in the wall plane
  std::unique_ptr<float[]> wall_v_m;
  // The side width test's last raised run in each column (rows
  // [first, last], its width and peak), so that each run is measured once.
  static constexpr std::size_t kMaxWidth = 4096;
  std::unique_ptr<std::int32_t[]> column_run_first;
  std::unique_ptr<std::int32_t[]> column_run_last;
  std::unique_ptr<float[]> column_run_width_m;
  std::unique_ptr<float[]> column_run_peak_m;
  std::unique_ptr<float[]> column_run_base_m;
  // The cross test's probes (handrail_filters.cpp, WallPairs): per pixel,
  // how many rows below it (at most 255) the first row in its column
  // starts where two wall pixels stand one above the other.
  std::unique_ptr<std::uint8_t[]> column_wall_pair_rows_down;
  // Contiguous copies of the RANSAC subsamples ((x, y, z), or (u, v) in the
  // wall plane), so that scoring a hypothesis streams through memory
  // instead of hopping through the cloud.
  static constexpr std::size_t kMaxScoreSamples = 4096;
  static constexpr std::size_t kMaxRefitSamples = 2000;
  std::unique_ptr<float[]> score_x_m;
  std::unique_ptr<float[]> score_y_m;
  std::unique_ptr<float[]> score_z_m;
  std::unique_ptr<float[]> refit_x_m;
  std::unique_ptr<float[]> refit_y_m;
  std::unique_ptr<float[]> refit_z_m;

  std::size_t bytes() const;
};

}  // namespace estimator
