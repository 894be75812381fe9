#pragma once
#include <string>

namespace fsw_app {

// A process that hears depth frames over udpm (an estimator fed from
// another process, or a log that records this process's own frames) needs
// a socket receive buffer of several frames: with the kernel's default of
// about 200 kB, 8 of 89 frames reached the log. Adds recv_buf_size to the
// URL. False, with *error saying what to set, when the kernel's limit is
// below it.
bool with_frame_receive_buffer(std::string* url, std::string* error);

}  // namespace fsw_app
