#pragma once
// royale's events: what a camera device reports beside its frames (its
// stream's health, a lost camera), with royale's severities and types.
#include "royale/Definitions.hpp"

namespace royale {

enum class EventSeverity {
  ROYALE_INFO = 0,     // for information
  ROYALE_WARNING = 1,  // a possible problem (frames dropped)
  ROYALE_ERROR = 2,    // an operation failed and stopped
  ROYALE_FATAL = 3,    // the device is no longer usable
};

enum class EventType {
  ROYALE_CAPTURE_STREAM,       // the frames' way in
  ROYALE_DEVICE_DISCONNECTED,  // the camera is gone (always ROYALE_FATAL)
  ROYALE_OVER_TEMPERATURE,
  ROYALE_RAW_FRAME_STATS,  // about once a second while capturing: frames in and dropped
  ROYALE_EYE_SAFETY,
  ROYALE_PROCESSING,
  ROYALE_RECORDING,
  ROYALE_FRAME_DROP,
  ROYALE_UNKNOWN,
};

class IEvent {
 public:
  virtual ~IEvent() = default;
  virtual royale::EventSeverity severity() const = 0;
  // For developers, not for parsing: what happened, in words.
  virtual const royale::String describe() const = 0;
  virtual royale::EventType type() const = 0;
};

}  // namespace royale
