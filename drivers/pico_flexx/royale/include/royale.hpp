#pragma once
// royale's umbrella header: the royale C++ API on the project's Pico Flexx
// driver (drivers/pico_flexx/README.md, "royale", says which part).
#include "royale/CameraManager.hpp"
#include "royale/Definitions.hpp"
#include "royale/DepthData.hpp"
#include "royale/ExposureMode.hpp"
#include "royale/ICameraDevice.hpp"
#include "royale/IDepthDataListener.hpp"
#include "royale/IEvent.hpp"
#include "royale/IEventListener.hpp"
#include "royale/LensParameters.hpp"
#include "royale/Status.hpp"
