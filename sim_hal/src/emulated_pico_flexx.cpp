// The emulated Pico Flexx's USB side: the umockdev testbed, the device's
// sysfs entry and descriptors, and the usbdevfs requests libusb makes.
//
// The handler runs in this process (umockdev's worker thread), so the
// host's URBs and buffers are read and written where they are; the
// request's data is not copied through umockdev's socket. A URB completes
// by being queued for the host's next REAPURBNDELAY.
#include <linux/ioctl.h>
#include <linux/usbdevice_fs.h>
#include <umockdev.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>

#include "emulated_pico_flexx_impl.hpp"

namespace sim_hal {
namespace {

// Device descriptor, then the configuration: one vendor-specific interface
// with bulk OUT 0x01 (commands), bulk IN 0x81 (replies) and 0x82 (raw
// frames), 512-byte packets (high speed); 300 mA.
constexpr const char* kDescriptorsHex =
    // device: USB 2.00, class per interface, EP0 64 bytes, 1c28:c012 (little-endian),
    // release 1.00, strings 1 2 3, one configuration
    "1201000200000040"
    "281c"
    "12c0"
    "0001"
    "010203"
    "01"
    // configuration 1: 39 bytes in all, one interface, bus powered, 300 mA
    "09022700010100"
    "80"
    "96"
    // interface 0: three endpoints, class 0xff (vendor specific)
    "09040000"
    "03"
    "ff0000"
    "00"
    // endpoints: 0x01 OUT, 0x81 IN, 0x82 IN; bulk, 512 bytes
    "0705010200"
    "0200"
    "0705810200"
    "0200"
    "0705820200"
    "0200";

constexpr int kBusNumber = 1;
// How long a reap with nothing ready is held before "nothing yet" is
// answered. The kernel's poll() on a usbdevfs node blocks the host's event
// loop until a URB completes; umockdev does not emulate poll() (the node is
// always ready), so libusb would ask again at once, and the loop and this
// thread spun at over half a core each in a perch. Held for 1 ms, the host
// waits much as it would on the kernel, frames are still made within a
// millisecond of being due (at most 45 fps: 22 ms apart), and commands
// gain at most a millisecond.
constexpr auto kIdleReapHold = std::chrono::microseconds(1000);

std::string device_record(int device_number, const std::string& serial) {
  char node[64];
  std::snprintf(node, sizeof node, "bus/usb/%03d/%03d", kBusNumber, device_number);
  std::string r;
  r += "P: /devices/pci0000:00/0000:00:14.0/usb1/1-1\n";
  r += std::string("N: ") + node + "\n";
  r += "E: SUBSYSTEM=usb\n";
  r += "E: DEVTYPE=usb_device\n";
  r += "E: DRIVER=usb\n";
  r += std::string("E: DEVNAME=/dev/") + node + "\n";
  char line[64];
  std::snprintf(line, sizeof line, "E: BUSNUM=%03d\nE: DEVNUM=%03d\n", kBusNumber, device_number);
  r += line;
  std::snprintf(line, sizeof line, "A: busnum=%d\\n\nA: devnum=%d\\n\n", kBusNumber, device_number);
  r += line;
  r += "A: speed=480\\n\n";
  r += "A: bConfigurationValue=1\\n\n";
  r += "A: idVendor=1c28\\n\n";
  r += "A: idProduct=c012\\n\n";
  r += "A: serial=" + serial + "\\n\n";
  r += std::string("H: descriptors=") + kDescriptorsHex + "\n";
  return r;
}

void complete(UMockdevIoctlClient* client, long result, int error) {
  umockdev_ioctl_client_complete(client, result, error);
}

// The request's argument as the host passed it (a pointer or a value).
std::uintptr_t argument(UMockdevIoctlClient* client) {
  UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(client);
  std::uintptr_t value = 0;
  std::memcpy(&value, arg->data, sizeof value);
  return value;
}

bool remove_urb(std::deque<usbdevfs_urb*>* queue, usbdevfs_urb* urb) {
  for (auto it = queue->begin(); it != queue->end(); ++it) {
    if (*it == urb) {
      queue->erase(it);
      return true;
    }
  }
  return false;
}

gboolean handle_ioctl(UMockdevIoctlBase*, UMockdevIoctlClient* client, gpointer user_data) {
  auto* plug = static_cast<PlugContext*>(user_data);
  EmulatedPicoFlexx::Impl& d = *plug->impl;
  const unsigned long request = umockdev_ioctl_client_get_request(client);
  std::unique_lock<std::mutex> lock(d.mutex);
  bool present = d.plugged && plug->generation == d.generation;

  if (request == USBDEVFS_GET_CAPABILITIES) {
    if (!present) return complete(client, -1, ENODEV), TRUE;
    auto* caps = reinterpret_cast<std::uint32_t*>(argument(client));
    *caps = USBDEVFS_CAP_BULK_SCATTER_GATHER | USBDEVFS_CAP_NO_PACKET_SIZE_LIM |
            USBDEVFS_CAP_REAP_AFTER_DISCONNECT | USBDEVFS_CAP_ZERO_PACKET;
    complete(client, 0, 0);
    return TRUE;
  }
  if (request == USBDEVFS_REAPURBNDELAY || request == USBDEVFS_REAPURB) {
    // After an unplug the host still reaps what it had in flight, as shut
    // down; then the node answers ENODEV.
    if (present) d.advance(d.clock->now_us());
    if (present && d.done_urbs.empty()) {
      // Unlocked meanwhile, so that faults switched from other threads go
      // on; the host's other requests queue behind this one on the
      // worker thread, as they do anyway.
      lock.unlock();
      std::this_thread::sleep_for(kIdleReapHold);
      lock.lock();
      present = d.plugged && plug->generation == d.generation;
      if (present) d.advance(d.clock->now_us());
    }
    if (d.done_urbs.empty()) {
      complete(client, -1, present ? EAGAIN : ENODEV);
      return TRUE;
    }
    usbdevfs_urb* urb = d.done_urbs.front();
    d.done_urbs.pop_front();
    ++d.counts.urbs_reaped;
    *reinterpret_cast<void**>(argument(client)) = urb;
    complete(client, 0, 0);
    return TRUE;
  }
  if (!present) {
    complete(client, -1, ENODEV);
    return TRUE;
  }
  switch (request) {
    case USBDEVFS_CLAIMINTERFACE:
    case USBDEVFS_RELEASEINTERFACE:
    case USBDEVFS_SETINTERFACE:
    case USBDEVFS_SETCONFIGURATION:
    case USBDEVFS_RESETEP:
      complete(client, 0, 0);
      return TRUE;
    case USBDEVFS_GETDRIVER:
    case USBDEVFS_IOCTL:
      complete(client, -1, ENODATA);  // no kernel driver bound
      return TRUE;
    case USBDEVFS_CLEAR_HALT: {
      const unsigned endpoint = *reinterpret_cast<unsigned*>(argument(client));
      if (endpoint == pico_flexx::kStreamEndpoint && !d.halt_persistent) d.stream_halted = false;
      ++d.counts.clear_halts;
      complete(client, 0, 0);
      return TRUE;
    }
    case USBDEVFS_RESET: {
      // The camera restarts: in-flight transfers end, settings revert.
      ++d.counts.resets;
      for (auto* q : {&d.command_urbs, &d.reply_urbs, &d.stream_urbs}) {
        for (usbdevfs_urb* urb : *q) {
          urb->status = -ENOENT;
          urb->actual_length = 0;
          d.done_urbs.push_back(urb);
        }
        q->clear();
      }
      d.power_up();
      complete(client, 0, 0);
      return TRUE;
    }
    case USBDEVFS_SUBMITURB: {
      auto* urb = reinterpret_cast<usbdevfs_urb*>(argument(client));
      if (urb->type != USBDEVFS_URB_TYPE_BULK) {
        complete(client, -1, EINVAL);
        return TRUE;
      }
      ++d.counts.urbs_submitted;
      if (urb->endpoint == pico_flexx::kCommandEndpoint) {
        d.execute_command(static_cast<const std::uint8_t*>(urb->buffer),
                          static_cast<std::size_t>(urb->buffer_length));
        urb->status = 0;
        urb->actual_length = urb->buffer_length;
        d.done_urbs.push_back(urb);
      } else if (urb->endpoint == pico_flexx::kReplyEndpoint) {
        d.reply_urbs.push_back(urb);
      } else if (urb->endpoint == pico_flexx::kStreamEndpoint) {
        d.stream_urbs.push_back(urb);
      } else {
        complete(client, -1, ENOENT);
        return TRUE;
      }
      d.advance(d.clock->now_us());
      complete(client, 0, 0);
      return TRUE;
    }
    case USBDEVFS_DISCARDURB: {
      auto* urb = reinterpret_cast<usbdevfs_urb*>(argument(client));
      if (remove_urb(&d.reply_urbs, urb) || remove_urb(&d.stream_urbs, urb) ||
          remove_urb(&d.command_urbs, urb)) {
        urb->status = -ENOENT;
        urb->actual_length = 0;
        d.done_urbs.push_back(urb);
        ++d.counts.urbs_discarded;
        complete(client, 0, 0);
      } else {
        complete(client, -1, EINVAL);  // already finished: the host reaps it
      }
      return TRUE;
    }
    default:
      return FALSE;  // umockdev's default: ENOTTY
  }
}

}  // namespace

bool EmulatedPicoFlexx::Impl::add_device(std::string* error) {
  auto* plug = new PlugContext;
  plug->impl = this;
  {
    std::lock_guard<std::mutex> lock(mutex);
    plug->generation = ++generation;
  }
  // Device numbers start at 2 (1 is the root hub) and grow with each plug.
  const int device_number = 1 + plug->generation;
  char node[64];
  std::snprintf(node, sizeof node, "/dev/bus/usb/%03d/%03d", kBusNumber, device_number);
  plug->node = node;
  plug->handler = umockdev_ioctl_base_new();
  g_signal_connect(plug->handler, "handle-ioctl", G_CALLBACK(handle_ioctl), plug);
  plugs.push_back(plug);
  GError* gerror = nullptr;
  // The handler first, so that a host that opens the node on the "add"
  // event finds it answered.
  if (!umockdev_testbed_attach_ioctl(testbed, node, plug->handler, &gerror)) {
    *error = std::string("emulated camera: attaching the ioctl handler to ") + node + ": " +
             (gerror ? gerror->message : "unknown error");
    if (gerror) g_error_free(gerror);
    return false;
  }
  {
    std::lock_guard<std::mutex> lock(mutex);
    power_up();
    plugged = true;
    ++counts.plugs;
  }
  if (!umockdev_testbed_add_from_string(
          testbed, device_record(device_number, config.serial).c_str(), &gerror)) {
    *error = std::string("emulated camera: the testbed refused the device: ") +
             (gerror ? gerror->message : "unknown error");
    if (gerror) g_error_free(gerror);
    return false;
  }
  plug->syspath = "/sys/devices/pci0000:00/0000:00:14.0/usb1/1-1";
  return true;
}

std::unique_ptr<EmulatedPicoFlexx> EmulatedPicoFlexx::create(const EmulatedCameraConfig& config,
                                                             RawFrameSource* source,
                                                             const hal::Clock& clock,
                                                             std::string* error) {
  // umockdev_in_mock_environment() only says so once a testbed exists.
  const char* preload = std::getenv("LD_PRELOAD");
  if (preload == nullptr || std::strstr(preload, "libumockdev-preload") == nullptr) {
    *error =
        "emulated camera: not running under umockdev's preload library (start the program with "
        "umockdev-wrapper, or LD_PRELOAD=libumockdev-preload.so.0)";
    return nullptr;
  }
  auto impl = std::make_unique<Impl>();
  impl->config = config;
  impl->source = source;
  impl->clock = &clock;
  impl->frame_bytes.resize(pico_flexx::kFrameHeaderBytes + pico_flexx::kMaxRawPayloadBytes());
  impl->testbed = umockdev_testbed_new();
  if (!impl->add_device(error)) return nullptr;
  return std::unique_ptr<EmulatedPicoFlexx>(new EmulatedPicoFlexx(std::move(impl)));
}

EmulatedPicoFlexx::EmulatedPicoFlexx(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

EmulatedPicoFlexx::~EmulatedPicoFlexx() {
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->plugged = false;
  }
  g_object_unref(impl_->testbed);
  for (PlugContext* plug : impl_->plugs) {
    g_object_unref(plug->handler);
    delete plug;
  }
}

void EmulatedPicoFlexx::unplug() {
  Impl& d = *impl_;
  const std::string syspath = d.plugs.back()->syspath;
  {
    std::lock_guard<std::mutex> lock(d.mutex);
    if (!d.plugged) return;
    d.plugged = false;
    d.streaming = false;
    ++d.counts.unplugs;
    // What the host had in flight comes back as shut down.
    for (auto* q : {&d.command_urbs, &d.reply_urbs, &d.stream_urbs}) {
      for (usbdevfs_urb* urb : *q) {
        urb->status = -ESHUTDOWN;
        urb->actual_length = 0;
        d.done_urbs.push_back(urb);
      }
      q->clear();
    }
  }
  umockdev_testbed_uevent(d.testbed, syspath.c_str(), "remove");
  umockdev_testbed_remove_device(d.testbed, syspath.c_str());
}

bool EmulatedPicoFlexx::replug(std::string* error) {
  return impl_->add_device(error);
}

void EmulatedPicoFlexx::stall_stream(bool persistent) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->stream_halted = true;
  impl_->halt_persistent = persistent;
}
void EmulatedPicoFlexx::set_silent(bool silent) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->silent = silent;
}
void EmulatedPicoFlexx::corrupt_next_frames(int frames) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->corrupt_frames += frames;
}
void EmulatedPicoFlexx::shorten_next_frames(int frames) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->short_frames += frames;
}
void EmulatedPicoFlexx::corrupt_next_headers(int frames) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->corrupt_headers += frames;
}
void EmulatedPicoFlexx::clear_frame_faults() {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->corrupt_frames = 0;
  impl_->short_frames = 0;
  impl_->corrupt_headers = 0;
}
void EmulatedPicoFlexx::mute_next_commands(int commands) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->muted_commands += commands;
}
void EmulatedPicoFlexx::set_reply_delay_us(std::int64_t delay_us) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->reply_delay_us = delay_us;
}

bool EmulatedPicoFlexx::capture_time_of(std::uint32_t sequence, std::int64_t* host_us) const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  for (const auto& entry : impl_->capture_log) {
    if (impl_->captures_logged > 0 && entry.first == sequence && entry.second != 0) {
      *host_us = entry.second;
      return true;
    }
  }
  return false;
}

EmulatorCounts EmulatedPicoFlexx::counts() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  EmulatorCounts c = impl_->counts;
  c.streaming = impl_->streaming;
  c.use_case_index = impl_->use_case_index;
  return c;
}

std::string EmulatedPicoFlexx::device_node() const {
  return impl_->plugs.back()->node;
}

}  // namespace sim_hal
