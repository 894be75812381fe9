#pragma once
// The run's LCM log (--log FILE): every message the process hears, written
// from the dispatcher thread. A write that fails (disk full, /dev/full, an
// I/O error) is not silent: logging ends at that message, the reason is
// kept, and the run's summary and exit status report it.
//
// stdio buffers the writes, and a full device shows only when a buffer
// reaches it: a message counts as recorded once a flush after it has
// succeeded (every kFlushEvery_us of the log's time, and at close). What
// sat in a buffer that failed to reach the device is counted as lost.
#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

namespace fsw_app {

class RunLog {
 public:
  // False, with *error naming the file, when it cannot be created.
  bool open(const std::string& path, std::string* error);
  bool is_open() const { return file_ != nullptr; }

  // LcmHub::RawSink: one message into the log.
  static void sink(void* user, const std::string& channel, const lcm::ReceiveBuffer& rbuf);

  // Flushes and closes the file; false when any write failed, including
  // the last flush (where buffered writes to a full disk show up).
  bool close();

  std::int64_t events() const;        // messages that reached the device
  std::int64_t depth_frames() const;  // DEPTH_FRAME among them
  std::int64_t lost() const;          // heard but not recorded (a write or flush failed)
  // Empty while every write succeeded; else what failed, and after how
  // many messages.
  std::string failure() const;

 private:
  void fail(const char* what, int err);
  // Flushes what is buffered; the buffered messages become recorded, or
  // lost when the flush fails. Under mutex_.
  void flush_buffered(const char* what);

  static constexpr std::int64_t kFlushEvery_us = 200'000;

  mutable std::mutex mutex_;
  std::unique_ptr<lcm::LogFile> file_;
  std::string path_;
  std::int64_t events_ = 0, depth_frames_ = 0, lost_ = 0;
  std::int64_t buffered_ = 0, buffered_depth_frames_ = 0;  // written, not yet flushed
  std::int64_t last_flush_utime_ = 0;
  std::string failure_;
};

}  // namespace fsw_app
