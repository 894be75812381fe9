#pragma once
// royale's umbrella header: the royale C++ API on the project's Pico Flexx
// driver (drivers/pico_flexx/README.md, "royale", says which part).
#include "royale/CameraAccessLevel.hpp"
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

namespace royale {

// The royale release whose level-1 calls this library follows (in part:
// drivers/pico_flexx/doc/royale.md): 3.21.0, build 0, no SCM revision.
void getVersion(unsigned& major, unsigned& minor, unsigned& patch);
void getVersion(unsigned& major, unsigned& minor, unsigned& patch, unsigned& build);
void getVersion(unsigned& major, unsigned& minor, unsigned& patch, unsigned& build,
                royale::String& scmRevision);

// A sentence, in English, for developers, on what a status means.
royale::String getErrorString(royale::CameraStatus status);

}  // namespace royale
