#include "run_log.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include <unistd.h>

namespace fsw_app {

bool RunLog::open(const std::string& path, std::string* error) {
  path_ = path;
  file_ = std::make_unique<lcm::LogFile>(path, "w");
  if (!file_->good()) {
    file_.reset();
    *error = path + ": cannot write the LCM log (" + std::strerror(errno) + ")";
    return false;
  }
  return true;
}

void RunLog::fail(const char* what, int err) {
  failure_ = std::string(what) + " failed after " + std::to_string(events_) +
             " messages recorded: " + std::strerror(err != 0 ? err : EIO);
}

void RunLog::flush_buffered(const char* what) {
  std::FILE* f = file_->getFilePtr();
  errno = 0;
  if (std::fflush(f) != 0 || std::ferror(f)) {
    if (failure_.empty()) fail(what, errno);
    lost_ += buffered_;
  } else {
    events_ += buffered_;
    depth_frames_ += buffered_depth_frames_;
  }
  buffered_ = buffered_depth_frames_ = 0;
}

void RunLog::sink(void* user, const std::string& channel, const lcm::ReceiveBuffer& rbuf) {
  auto* self = static_cast<RunLog*>(user);
  std::lock_guard<std::mutex> lock(self->mutex_);
  if (!self->file_ || !self->failure_.empty()) {
    ++self->lost_;
    return;
  }
  lcm::LogEvent e;
  e.eventnum = self->events_;
  e.timestamp = rbuf.recv_utime;
  e.channel = channel;
  e.datalen = static_cast<std::int32_t>(rbuf.data_size);
  e.data = rbuf.data;
  errno = 0;
  // stdio buffers: a full disk may show as a short write now or as an
  // error flag on the stream; either ends the log here.
  if (self->file_->writeEvent(&e) != 0 || std::ferror(self->file_->getFilePtr())) {
    self->fail("writing", errno);
    self->lost_ += self->buffered_ + 1;
    self->buffered_ = self->buffered_depth_frames_ = 0;
    return;
  }
  ++self->buffered_;
  if (channel == "DEPTH_FRAME") ++self->buffered_depth_frames_;
  if (rbuf.recv_utime - self->last_flush_utime_ >= kFlushEvery_us) {
    self->last_flush_utime_ = rbuf.recv_utime;
    self->flush_buffered("writing");
  }
}

bool RunLog::close() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!file_) return failure_.empty();
  std::FILE* f = file_->getFilePtr();
  if (failure_.empty()) {
    flush_buffered("flushing");
  } else {
    lost_ += buffered_;
    buffered_ = buffered_depth_frames_ = 0;
  }
  errno = 0;
  if (fsync(fileno(f)) != 0 && errno != EINVAL && errno != EROFS && failure_.empty()) {
    fail("syncing", errno);
  }
  file_.reset();
  return failure_.empty();
}

std::int64_t RunLog::events() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return events_;
}
std::int64_t RunLog::depth_frames() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return depth_frames_;
}
std::int64_t RunLog::lost() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return lost_;
}
std::string RunLog::failure() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return failure_;
}

}  // namespace fsw_app
