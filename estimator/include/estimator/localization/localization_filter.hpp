#pragma once
// The localization filter: an error-state EKF on IMU samples, corrected by
// general-purpose (GP) localizer poses and handrail measurements (the
// paper's "Localization" section), each applied at its capture time.
//
// An fsw_app localization task drives it from one thread:
//   add_imu()        every IMU sample (62.5 Hz), in time order
//   add_gp_pose()    every GP pose, when it arrives (100 to 300 ms late)
//   add_handrail()   every handrail detection with features, when it arrives
//   estimate()       the pose at the newest IMU sample, with its covariance
// Every call returns a status (status.hpp) and is counted (counters()). No
// call allocates or throws; each does bounded work: an IMU sample at most
// kMaxGapSubsteps steps; a measurement at most one re-propagation over the
// history (kHistoryCapacity steps) re-applying at most kMaxStoredMeasurements
// stored updates. The object is large (about 160 kB, sizeof()): build it once.
//
// Rules:
//   Start. The first valid GP pose initialises the filter (kInitialized) at
//     its capture time, or the oldest sample held if older: position and
//     attitude from the pose with its covariance, velocity zero and biases
//     from the configuration with their sigmas. Before it, IMU samples are
//     only held (kBuffered) and handrail measurements are rejected
//     (kRejectedNotInitialized), as is a GP pose before any IMU sample (it
//     cannot be placed in time).
//   Late measurements. A measurement captured at t within the history is
//     applied to the state at t: the state there is re-created from the
//     sample before t (re-applying stored updates between the two), the
//     update is gated and applied, and the filter re-propagates to the newest
//     sample, re-applying (and re-gating) the stored updates captured after
//     t. Older than the history, or than a reset of it (initialisation,
//     relocalisation, a lost IMU gap): kRejectedTooOld. Captured after the
//     newest sample by up to max_future_s: applied at the newest; later:
//     kRejectedInFuture.
//   IMU gaps: imu_propagation.hpp.
//   GP jumps (relocalisation). A GP pose failing the gate is rejected
//     (kRejectedGate) and starts a pending jump. While the handrail holds the
//     pose (an update accepted within handrail_hold_s), that is all: the
//     handrail is the better reference when perching, and every jumped pose
//     is gated and rejected. Otherwise a pose that agrees with the pending
//     jump (its offset from the filter within relocalize_agreement_m and
//     _rad of the rejected one's, and not itself within those of the filter)
//     is held back with it (kRejectedJump) whatever the gate would say, since
//     the covariance grows while poses are rejected; relocalize_after poses
//     in a row (the first rejected by the gate, the rest agreeing) move the
//     filter to the newest of them (kRelocalized): position and attitude from
//     the pose with its covariance, velocity and biases kept; the stored
//     updates, the handrail map and the history before it dropped. A pose
//     near the filter again (a glitch that came back) goes through the gate
//     as usual and ends the pending jump. So a jump is never taken part way:
//     rejected whole, or taken whole after agreeing poses.
//   - Divergence: a filter whose velocity or biases went wrong (an IMU
//     glitch, a bad update) runs away from every fix at once, so the GP
//     poses it rejects never agree with each other's offsets and the jump
//     rule never moves it. reinitialize_after GP poses in a row rejected
//     (gate or jump, whatever their offsets) with no handrail holding the
//     pose start the filter again from the newest (kRelocalized, counted in
//     reinitializations): position and attitude from the pose, velocity zero
//     and biases from the configuration, the covariance as at the start;
//     the stored updates, the handrail map and the history before it
//     dropped. A pose accepted or the handrail holding resets the count.
//   Handrail. The map (handrail_map.hpp) is built from the first confident
//     sightings (kMapSighting, kMapInitialized). Sightings with no end seen
//     build a line map, its origin somewhere on the bar, which serves NE
//     updates from the first frames on; sightings with an end then count
//     toward a map placed along the bar (each used as NE meanwhile), which
//     replaces the line map when complete. The map completed goes into the
//     state with the robot's uncertainty at that time (map_state.hpp), an
//     event stored with the updates so that a re-propagation across it does
//     it again. With a map, each measurement is an update
//     (handrail_update.hpp); map_reset_after_rejections gate rejections in a
//     row drop the map (the handrail moved, or the map was wrong), and the
//     next confident sightings build it again. A surveyed map
//     (set_handrail_survey) replaces the sightings: it is the map from the
//     start, and wherever a map would be dropped (those rejections, a
//     relocalisation, reset_handrail_map, reset) the survey is put back.
//   Bad input. Anything non-finite or malformed is rejected before it
//     touches anything (kRejectedNotFinite, kRejectedInvalid,
//     kRejectedOutOfRange for IMU samples beyond the sensor's range).
#include <cstdint>

#include "estimator/localization/config.hpp"
#include "estimator/localization/ekf_update.hpp"
#include "estimator/localization/gates.hpp"
#include "estimator/localization/handrail_map.hpp"
#include "estimator/localization/history.hpp"
#include "estimator/localization/measurements.hpp"
#include "estimator/localization/state.hpp"
#include "estimator/localization/status.hpp"

namespace estimator::localization {

// The filter's output at its newest IMU sample.
struct PoseEstimate {
  bool initialized = false;
  bool lost = false;  // after a long IMU gap, until an absolute fix
  bool handrail_map_valid = false;
  bool handrail_holding = false;  // a handrail update accepted within handrail_hold_s
  std::int64_t t_us = 0;
  Eigen::Vector3d p_world_body_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_world_body_mps = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_world_body = Eigen::Quaterniond::Identity();
  Eigen::Vector3d gyro_bias_radps = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_bias_mps2 = Eigen::Vector3d::Zero();
  // [position, attitude (world)]: with a map, the map's own uncertainty
  // included (map_state.hpp).
  PoseCovariance pose_cov = PoseCovariance::Zero();
  Eigen::Matrix3d velocity_cov = Eigen::Matrix3d::Zero();
  // With a map: the body's position in the handrail's frame and its
  // covariance there, what the handrail updates know (zero without a map).
  Eigen::Vector3d p_handrail_body_m = Eigen::Vector3d::Zero();
  Eigen::Matrix3d handrail_position_cov = Eigen::Matrix3d::Zero();
};

class LocalizationFilter {
 public:
  explicit LocalizationFilter(const LocalizationConfig& cfg = LocalizationConfig{});

  // nullptr when the configuration is valid; otherwise the bad field, and
  // every input is rejected (kRejectedBadConfig).
  const char* config_error() const { return config_error_; }
  const LocalizationConfig& config() const { return cfg_; }

  ImuStatus add_imu(const ImuSample& s);
  UpdateStatus add_gp_pose(const GpPose& g);
  UpdateStatus add_handrail(const HandrailMeasurement& m);

  // Back to uninitialised (counters kept).
  void reset();
  // Forget the handrail map (a new perch target): the next confident
  // sightings build it again (or the survey is put back).
  void reset_handrail_map();
  // The handrail's surveyed world pose and its uncertainty (handrail_map.hpp)
  // as the map from now on, in place of its first sightings; stored
  // handrail updates made against an earlier map are dropped from
  // re-propagation. kAccepted, or check_survey()'s rejection (nothing
  // changed). clear_handrail_survey(): back to maps from sightings.
  UpdateStatus set_handrail_survey(const HandrailMap& survey);
  void clear_handrail_survey();

  bool initialized() const { return initialized_; }
  bool lost() const { return lost_; }
  bool handrail_holding() const;
  std::int64_t time_us() const;  // of the newest IMU sample (0 before any)
  // The state and covariance at the newest sample (defaults before
  // initialisation).
  const NominalState& state() const;
  const Covariance& covariance() const;
  PoseEstimate estimate() const;
  // The map as the filter holds it now: valid and surveyed from the map,
  // its pose from the state (which the updates move within its
  // uncertainty).
  HandrailMap handrail_map() const;
  const FilterCounters& counters() const { return counters_; }
  // NIS, dimension and features of the newest GP or handrail update tried.
  const UpdateResult& last_update() const { return last_; }
  // check_filter() of the newest state (kOk before initialisation).
  Health check() const;

 private:
  // The state at a time t inside the history, before a new measurement.
  struct Prior {
    int k = -1;  // history entry at or before t
    std::int64_t t_us = 0;
    NominalState x;
    Covariance P = Covariance::Identity();
    ImuSample s;         // the IMU sample interpolated at t
    int next_store = 0;  // first stored measurement after t
  };

  UpdateStatus time_check(std::int64_t t_us, std::int64_t* t_eff) const;
  bool prior_at(std::int64_t t_us, Prior* pr);
  void replay(int k, NominalState x, Covariance P, ImuSample s_prev, int cursor);
  void apply_stored(const StoredMeasurement& m, NominalState* x, Covariance* P);
  void store_and_replay(const StoredMeasurement& m, const Prior& pr, const NominalState& x,
                        const Covariance& P);
  // Sets the state at pr's time (a fresh start: the history before is cut).
  void restart_at(const Prior& pr, const NominalState& x, const Covariance& P);
  UpdateStatus initialize_from(const GpPose& g, std::int64_t t_eff);
  // reset_dynamics: velocity and biases from the configuration as well,
  // the whole covariance as at the start (a diverged filter's are suspect).
  UpdateStatus relocalize_to(const GpPose& g, const Prior& pr, bool reset_dynamics);
  void drop_map();
  // The survey, when one is set, into the newest state (after a drop).
  void put_back_survey();
  // The map into the state at pr's time, stored so that a re-propagation
  // across that time does it again.
  void attach_map_at(const Prior& pr, const HandrailMap& map);
  void raise_floor_past(std::int64_t t_us);

  LocalizationConfig cfg_;
  const char* config_error_ = nullptr;
  ChiSquareGate gate_;
  ImuHistory history_;
  MeasurementStore store_;
  HandrailMapBuilder map_;
  HandrailMapBuilder ends_map_;  // counting toward a map with ends, while map_ is a line
  HandrailMap survey_;           // valid when a survey is set
  std::uint32_t map_generation_ = 0;
  FilterCounters counters_;
  UpdateResult last_;
  bool initialized_ = false;
  bool lost_ = false;
  std::int64_t floor_us_ = 0;  // measurements before it: too old
  std::uint32_t seq_ = 0;
  bool have_handrail_accept_ = false;
  std::int64_t last_handrail_accept_us_ = 0;
  int handrail_rejections_in_row_ = 0;
  int gp_rejections_in_row_ = 0;
  int gp_any_rejections_in_row_ = 0;  // whatever their offsets (divergence)
  Eigen::Vector3d last_rejected_dp_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d last_rejected_dtheta_ = Eigen::Vector3d::Zero();
  NominalState default_state_;
  Covariance default_P_ = Covariance::Identity();
  // Scratch for one measurement, a member so that the stack stays small.
  StoredMeasurement scratch_;
  Prior prior_;
};

}  // namespace estimator::localization
