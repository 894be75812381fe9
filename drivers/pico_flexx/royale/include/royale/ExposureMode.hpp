#pragma once

namespace royale {

// MANUAL: the application sets the exposure time within the use case's
// limits; AUTOMATIC: the camera chooses it per frame.
enum class ExposureMode { MANUAL, AUTOMATIC };

}  // namespace royale
