#include "estimator/localization/status.hpp"

namespace estimator::localization {

const char* to_string(ImuStatus s) {
  switch (s) {
    case ImuStatus::kPropagated:
      return "PROPAGATED";
    case ImuStatus::kGapBridged:
      return "GAP_BRIDGED";
    case ImuStatus::kGapLost:
      return "GAP_LOST";
    case ImuStatus::kBuffered:
      return "BUFFERED";
    case ImuStatus::kRejectedNotFinite:
      return "REJECTED_NOT_FINITE";
    case ImuStatus::kRejectedOutOfRange:
      return "REJECTED_OUT_OF_RANGE";
    case ImuStatus::kRejectedOutOfOrder:
      return "REJECTED_OUT_OF_ORDER";
    case ImuStatus::kRejectedBadConfig:
      return "REJECTED_BAD_CONFIG";
  }
  return "UNKNOWN";
}

const char* to_string(UpdateStatus s) {
  switch (s) {
    case UpdateStatus::kAccepted:
      return "ACCEPTED";
    case UpdateStatus::kInitialized:
      return "INITIALIZED";
    case UpdateStatus::kRelocalized:
      return "RELOCALIZED";
    case UpdateStatus::kMapSighting:
      return "MAP_SIGHTING";
    case UpdateStatus::kMapInitialized:
      return "MAP_INITIALIZED";
    case UpdateStatus::kNoMap:
      return "NO_MAP";
    case UpdateStatus::kRejectedGate:
      return "REJECTED_GATE";
    case UpdateStatus::kRejectedJump:
      return "REJECTED_JUMP";
    case UpdateStatus::kRejectedNotFinite:
      return "REJECTED_NOT_FINITE";
    case UpdateStatus::kRejectedInvalid:
      return "REJECTED_INVALID";
    case UpdateStatus::kRejectedTooFewFeatures:
      return "REJECTED_TOO_FEW_FEATURES";
    case UpdateStatus::kRejectedTooOld:
      return "REJECTED_TOO_OLD";
    case UpdateStatus::kRejectedInFuture:
      return "REJECTED_IN_FUTURE";
    case UpdateStatus::kRejectedNotInitialized:
      return "REJECTED_NOT_INITIALIZED";
    case UpdateStatus::kRejectedNumerical:
      return "REJECTED_NUMERICAL";
    case UpdateStatus::kRejectedBadConfig:
      return "REJECTED_BAD_CONFIG";
  }
  return "UNKNOWN";
}

const char* to_string(MeasurementKind k) {
  switch (k) {
    case MeasurementKind::kGpPose:
      return "GP_POSE";
    case MeasurementKind::kHandrailEnds:
      return "HANDRAIL_ENDS";
    case MeasurementKind::kHandrailNoEnd:
      return "HANDRAIL_NO_END";
  }
  return "UNKNOWN";
}

const char* to_string(Health h) {
  switch (h) {
    case Health::kOk:
      return "OK";
    case Health::kStateNotFinite:
      return "STATE_NOT_FINITE";
    case Health::kQuaternionNotUnit:
      return "QUATERNION_NOT_UNIT";
    case Health::kNotFinite:
      return "NOT_FINITE";
    case Health::kNotSymmetric:
      return "NOT_SYMMETRIC";
    case Health::kNotPositiveDefinite:
      return "NOT_POSITIVE_DEFINITE";
  }
  return "UNKNOWN";
}

}  // namespace estimator::localization
