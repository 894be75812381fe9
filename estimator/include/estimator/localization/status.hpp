#pragma once
// What the localization filter did with each input, and the health of its
// state. Every input gets one of these; none is an exception.
#include <cstdint>

namespace estimator::localization {

// An IMU sample.
enum class ImuStatus : std::uint8_t {
  kPropagated,          // one step (up to max_imu_step_s)
  kGapBridged,          // a gap up to max_imu_gap_s: sub-steps, extra noise
  kGapLost,             // a longer gap: not integrated; covariance inflated,
                        // the estimate flagged lost until an absolute fix
  kBuffered,            // before initialisation: kept for re-propagation
  kRejectedNotFinite,   // NaN or infinity in a rate or acceleration
  kRejectedOutOfRange,  // beyond max_rate_radps or max_accel_mps2
  kRejectedOutOfOrder,  // not later than the previous sample
  kRejectedBadConfig,   // the filter's configuration failed validate()
};
constexpr int kNumImuStatus = 8;
const char* to_string(ImuStatus s);

// A general-purpose (GP) pose or a handrail measurement.
enum class UpdateStatus : std::uint8_t {
  kAccepted,                // passed the gate, applied at its capture time
  kInitialized,             // the first GP pose: the filter starts from it
  kRelocalized,             // GP poses agreeing on a jump: the filter moved to them
  kMapSighting,             // a handrail sighting stored to build the map
  kMapInitialized,          // the sighting that completed the handrail map
  kNoMap,                   // handrail seen, but no map yet and this sighting
                            // cannot add to one (pose too uncertain, or no end
                            // seen while sightings with ends are counted)
  kRejectedGate,            // chi-square gate
  kRejectedJump,            // a GP pose agreeing with a jump the gate rejected just
                            // before: held back with it (relocalisation rule)
  kRejectedNotFinite,       // NaN or infinity anywhere in the input
  kRejectedInvalid,         // malformed: covariance not positive definite,
                            // quaternion or rotation not unit, bad state or count
  kRejectedTooFewFeatures,  // fewer usable features than min_features
  kRejectedTooOld,          // captured before the history (or a reset) begins
  kRejectedInFuture,        // captured after the newest IMU sample + max_future_s
  kRejectedNotInitialized,  // a handrail measurement before any GP pose
  kRejectedNumerical,       // innovation covariance or result not positive definite
  kRejectedBadConfig,       // the filter's configuration failed validate()
};
constexpr int kNumUpdateStatus = 16;
const char* to_string(UpdateStatus s);
inline bool is_rejection(UpdateStatus s) {
  return static_cast<int>(s) >= static_cast<int>(UpdateStatus::kRejectedGate);
}

// Which measurement model: counters are kept per kind.
enum class MeasurementKind : std::uint8_t {
  kGpPose,         // 6-D pose residual
  kHandrailEnds,   // BE or OE: 3-D feature residuals (eqs. 6 to 10)
  kHandrailNoEnd,  // NE: 2-D residuals in the handrail frame (eqs. 11 to 13)
};
constexpr int kNumMeasurementKinds = 3;
const char* to_string(MeasurementKind k);

// The filter's state and covariance (check_filter) or a covariance alone.
enum class Health : std::uint8_t {
  kOk,
  kStateNotFinite,
  kQuaternionNotUnit,
  kNotFinite,            // the covariance holds a NaN or infinity
  kNotSymmetric,         // beyond rounding
  kNotPositiveDefinite,  // Cholesky fails or a variance is not positive
};
const char* to_string(Health h);

}  // namespace estimator::localization
