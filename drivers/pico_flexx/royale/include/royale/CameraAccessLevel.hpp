#pragma once
// royale's access levels. Level 1 is every application's; the higher ones
// (processing parameters, raw data, calibration, then eye-safety limits
// lifted) need PMD's activation codes. This implementation offers level 1
// only: a level-2 call returns INSUFFICIENT_PRIVILEGES, as royale does
// without a code.
namespace royale {

enum class CameraAccessLevel { L1 = 1, L2 = 2, L3 = 3, L4 = 4 };

}  // namespace royale
