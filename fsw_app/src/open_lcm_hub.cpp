#include "open_lcm_hub.hpp"

#include <cstdio>

namespace fsw_app {

std::optional<int> open_lcm_hub(const Options& opt, AppConfig* cfg, std::unique_ptr<LcmHub>* hub) {
  *hub = std::make_unique<LcmHub>(cfg->lcm_url);
  if (!(*hub)->good() && opt.hal == "sim" && opt.tasks == kAllTasks && opt.lcm_url.empty()) {
    // A hardware-in-loop run with every task in this process needs no
    // network: on a machine without a multicast route (a container, no
    // default route) it runs in-process rather than not at all. Never on
    // the robot (--hal real), and never when the URL was asked for.
    std::fprintf(stderr,
                 "fsw_app: LCM would not start on %s (no multicast route?); every task of this "
                 "run is in this process, so it runs on memq:// instead. To watch it with "
                 "lcm-spy, add the route: sudo ip link set lo multicast on; sudo ip route add "
                 "224.0.0.0/4 dev lo\n",
                 cfg->lcm_url.c_str());
    cfg->lcm_url = "memq://";
    *hub = std::make_unique<LcmHub>(cfg->lcm_url);
  }
  if (!(*hub)->good()) {
    std::fprintf(stderr,
                 "fsw_app: LCM would not start on %s. For udpm on one host add the multicast "
                 "route: sudo ip link set lo multicast on; sudo ip route add 224.0.0.0/4 dev lo\n",
                 cfg->lcm_url.c_str());
    return 1;
  }
  return std::nullopt;
}

}  // namespace fsw_app
