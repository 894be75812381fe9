#pragma once
// The whole per-frame pipeline of the paper, in fixed memory: every buffer
// is allocated by the constructor, detect() allocates nothing, throws
// nothing and does bounded work.
#include <cstdint>

#include "estimator/config.hpp"
#include "estimator/handrail_pose.hpp"
#include "estimator/line_estimation.hpp"
#include "estimator/line_trace.hpp"
#include "estimator/mount_surfaces.hpp"
#include "estimator/organized_cloud.hpp"
#include "estimator/pixel_scale.hpp"
#include "estimator/random.hpp"
#include "estimator/types.hpp"
#include "estimator/workspace.hpp"

namespace estimator {

// Injected time source for the frame budget (monotonic microseconds).
class TimeSource {
 public:
  virtual ~TimeSource() = default;
  virtual std::int64_t now_us() const = 0;
};

// std::chrono::steady_clock.
class SteadyTimeSource final : public TimeSource {
 public:
  std::int64_t now_us() const override;
};

enum class Method : std::uint8_t {
  kProposed,  // the paper's detector
  kBasic,     // plane RANSAC, then line RANSAC on the plane's outliers
};
const char* to_string(Method method);

class HandrailDetector {
 public:
  // The config must pass validate(); time may be null (the steady clock).
  explicit HandrailDetector(const DetectorConfig& cfg, const TimeSource* time = nullptr);

  HandrailDetection detect(const OrganizedCloud& cloud, Method method = Method::kProposed);

  const DetectorConfig& config() const { return cfg_; }
  // The last frame's per-pixel flags and sets, for debug images.
  const Workspace& workspace() const { return ws_; }
  const Plane& last_wall() const { return wall_; }
  // The last frame's surfaces in view and mounts (none when it had no
  // plane), for diagnostics.
  const MountHypotheses& last_mounts() const { return mounts_; }
  // ... and the dominant plane they are measured from (zero normal: none).
  const Plane& last_dominant_plane() const { return dominant_; }
  // Every line the last frame put to the tests, with its verdict, when
  // set_line_trace(true) (line_trace.hpp); empty otherwise.
  void set_line_trace(bool on) { trace_on_ = on; }
  const LineTrace& last_line_trace() const { return trace_; }

 private:
  // 45 deg: the half-width of Algorithm 1's angle families and of the
  // gripper's acceptance (the searches in both source files use it).
  static constexpr float kQuarterPi = 0.78539816f;
  bool over_budget(std::int64_t start_us) const;
  void clear_flags(const OrganizedCloud& cloud);
  void run_proposed(const OrganizedCloud& cloud, std::int64_t start_us, HandrailDetection* out);
  // The search on the mount offset_m from the dominant plane: wall_ set to
  // it, the gap distance pass against it (unless the workspace already
  // holds it), then search_on_mount(). Its random draws come from a stream
  // of its own, seeded from the frame and `slot` (the mount's, or
  // kMaxMountHypotheses for the plane), so no search's result depends on
  // what the searches before it drew, and a search run again repeats.
  void search_mount(const OrganizedCloud& cloud, const Plane& dominant, std::uint32_t slot,
                    float offset_m, bool run_gap_pass, std::int64_t start_us,
                    HandrailDetection* out);
  // The paper's tests and line search against the current wall_ (one mount
  // surface), after the gap distance pass has run against it.
  void search_on_mount(const OrganizedCloud& cloud, std::int64_t start_us, HandrailDetection* out);
  // Algorithm 2 and the verification of its lines on ws_.side, against
  // wall_ (the search's coordinates), repeated after rejected lines.
  void search_lines(const OrganizedCloud& cloud, std::int64_t start_us, HandrailDetection* out);
  // The bar-first search (DetectorConfig::bar_first): the bar runs
  // (bar_runs.hpp) as candidates, every line judged on its own surface.
  void run_bar_first(const OrganizedCloud& cloud, std::int64_t start_us, HandrailDetection* out);
  // Cluster, front height, centre line, ends and length of one line.
  LineVerdict verify_candidate(const OrganizedCloud& cloud, const LineModel& candidate,
                               const IndexList& points, LineModel* refined, IndexList& inliers,
                               CenterLine* line, bool ends[2], float end_t[2]);
  // verify_candidate on the searched wall, on the bar's own surface
  // (local_surface.hpp), and the
  // steps after the bar is seated on either.
  LineVerdict verify_on_searched_wall(const OrganizedCloud& cloud, const LineModel& refined,
                                      const IndexList& inliers, CenterLine* line, bool ends[2],
                                      float end_t[2]);
  LineVerdict verify_on_own_surface(const OrganizedCloud& cloud, const LineModel& refined,
                                    const IndexList& inliers, CenterLine* line, bool ends[2],
                                    float end_t[2]);
  LineVerdict verify_seated_line(const OrganizedCloud& cloud, const IndexList& inliers,
                                 CenterLine* line, bool ends[2], float end_t[2],
                                 bool on_searched_wall);
  // Makes a bar's own surface the searched wall while it lives.
  class OnLocalSurface {
   public:
    OnLocalSurface(HandrailDetector* d, const OrganizedCloud& cloud, const Plane& local);
    ~OnLocalSurface();
    OnLocalSurface(const OnLocalSurface&) = delete;
    OnLocalSurface& operator=(const OnLocalSurface&) = delete;

   private:
    HandrailDetector* d_;
    Plane wall_;
    float mount_m_;
    bool strict_;
  };
  // The front-height test against the surfaces in view; moves the line
  // onto the mount it finds.
  bool seat_on_mount(const OrganizedCloud& cloud, const IndexList& inliers, CenterLine* line) const;
  // Whether a find lies within 45 deg of the gripper's angle in the image,
  // and which of two finds over mounts is better.
  bool along_gripper(const HandrailDetection& d) const;
  bool better_find(const HandrailDetection& a, const HandrailDetection& b) const;
  // Adds a tested line to the trace (trace_on_).
  void trace_line(LineVerdict verdict, const IndexList& inliers, const CenterLine& line,
                  const bool ends[2], const float end_t[2]);
  // Takes a rejected line's points out of the search.
  void remove_rejected_line(LineVerdict verdict, const LineModel& refined, const CenterLine& line,
                            IndexList& active);
  void run_basic(const OrganizedCloud& cloud, HandrailDetection* out);
  void fill_pose(const Eigen::Vector3f& p_cam_center, const Eigen::Matrix3f& R_cam_handrail,
                 HandrailDetection* out) const;

  DetectorConfig cfg_;
  SteadyTimeSource steady_;
  const TimeSource* time_;
  Workspace ws_;
  Random rng_;
  std::uint64_t frame_id_ = 0;  // the frame being detected, for the fits' own random streams
  Plane wall_;                  // the mount being searched (the dominant plane, shifted)
  Plane dominant_;
  PixelScale scale_;
  MountHypotheses mounts_;       // of the current frame
  bool rack_faces_ = false;      // the current frame's plane found rack faces a step apart
  float search_mount_m_ = 0.0f;  // wall_'s offset from the dominant plane
  LineTrace trace_;
  bool trace_on_ = false;
  std::uint8_t search_index_ = 0;  // the current search, for the trace
  bool strict_mount_ = true;       // the front height from wall_ alone (the dominant plane)
};

}  // namespace estimator
