#pragma once
// Receives a camera device's events (IEvent.hpp), on a thread of the
// device's own, not the caller's.
#include <memory>

#include "royale/IEvent.hpp"

namespace royale {

class IEventListener {
 public:
  virtual ~IEventListener() = default;
  virtual void onEvent(std::unique_ptr<royale::IEvent>&& event) = 0;
};

}  // namespace royale
