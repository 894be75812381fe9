#pragma once
// The process's one LCM instance, opened on the configured URL. Its own
// step because of the fallback below: where it may run on memq:// instead
// is a rule about the whole run, not about LCM.
#include <memory>
#include <optional>

#include "app_options.hpp"
#include "fsw_app/app_config.hpp"
#include "fsw_app/lcm_hub.hpp"

namespace fsw_app {

// Opens *hub on cfg->lcm_url. A --hal sim run with every task here and no
// --lcm-url falls back to memq:// (and sets cfg->lcm_url to it) when udpm
// will not start. Returns an exit status (1) after printing the route to
// add, when LCM will not start.
std::optional<int> open_lcm_hub(const Options& opt, AppConfig* cfg, std::unique_ptr<LcmHub>* hub);

}  // namespace fsw_app
