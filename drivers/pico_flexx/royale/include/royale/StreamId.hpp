#pragma once
// As in royale: the type is in Definitions.hpp.
#include "royale/Definitions.hpp"
