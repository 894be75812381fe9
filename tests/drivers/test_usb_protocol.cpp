// The Pico Flexx USB protocol's codecs and the frame assembler, pure code
// with no USB: check values, round trips, refusals, and every way a frame
// is dropped. Runs on the robot's build too (under qemu-arm).
#include <algorithm>
#include <cstring>
#include <memory>
#include <vector>

#include "cmocka_cpp.hpp"
#include "hal/use_case.hpp"
#include "pico_flexx/frame_assembler.hpp"
#include "pico_flexx/usb_protocol.hpp"

namespace {

using namespace pico_flexx;

void test_checksums(void**) {
  const auto* digits = reinterpret_cast<const std::uint8_t*>("123456789");
  assert_int_equal(crc32(digits, 9), 0xCBF43926u);
  // Fletcher-32 of "abcde" and "abcdef" (the published check values).
  assert_int_equal(fletcher32(reinterpret_cast<const std::uint8_t*>("abcde"), 5), 0xF04FC729u);
  assert_int_equal(fletcher32(reinterpret_cast<const std::uint8_t*>("abcdef"), 6), 0x56502D2Au);
}

void test_command_round_trip_and_refusals(void**) {
  std::uint8_t packet[kMaxCommandBytes];
  const std::uint8_t payload[6] = {1, 2, 3, 4, 5, 6};
  const std::size_t n =
      encode_command(Command::kReadCalibration, 7, payload, 6, packet, sizeof packet);
  assert_int_equal(n, kPacketHeaderBytes + 6 + kCrcBytes);
  CommandView view;
  assert_int_equal(parse_command(packet, n, &view), ParseStatus::kOk);
  assert_int_equal(view.command, Command::kReadCalibration);
  assert_int_equal(view.tag, 7);
  assert_int_equal(view.payload_bytes, 6);
  assert_memory_equal(view.payload, payload, 6);
  // Too long a payload is not encoded.
  std::uint8_t big[kMaxCommandPayloadBytes + 1] = {};
  assert_int_equal(encode_command(Command::kIdentify, 1, big, sizeof big, packet, sizeof packet),
                   0);
  // A flipped bit, a cut packet, a wrong magic.
  packet[9] ^= 0x10;
  assert_int_equal(parse_command(packet, n, &view), ParseStatus::kBadCrc);
  packet[9] ^= 0x10;
  assert_int_equal(parse_command(packet, n - 1, &view), ParseStatus::kBadLength);
  packet[0] = 'X';
  assert_int_equal(parse_command(packet, n, &view), ParseStatus::kBadMagic);
}

void test_reply_matching(void**) {
  std::uint8_t packet[kMaxReplyBytes];
  const std::uint8_t payload[8] = {9, 8, 7, 6, 5, 4, 3, 2};
  const std::size_t n = encode_reply(Command::kCalibrationInfo, 42, ReplyStatus::kOk, payload, 8,
                                     packet, sizeof packet);
  ReplyView view;
  assert_int_equal(parse_reply(packet, n, Command::kCalibrationInfo, 42, &view), ParseStatus::kOk);
  assert_int_equal(view.status, ReplyStatus::kOk);
  assert_int_equal(view.payload_bytes, 8);
  assert_int_equal(parse_reply(packet, n, Command::kCalibrationInfo, 43, &view),
                   ParseStatus::kWrongTag);
  assert_int_equal(parse_reply(packet, n, Command::kIdentify, 42, &view),
                   ParseStatus::kWrongCommand);
  assert_int_equal(parse_reply(packet, 5, Command::kCalibrationInfo, 42, &view),
                   ParseStatus::kTooShort);
}

void test_identity_round_trip(void**) {
  Identity id;
  id.vendor_id = kVendorId;
  id.product_id = kProductId;
  id.protocol_version = 1;
  id.firmware_major = 2;
  id.firmware_minor = 9;
  std::strcpy(id.serial, "0005-1234-0042");
  std::uint8_t bytes[kIdentityBytes];
  encode_identity(id, bytes);
  Identity back;
  assert_true(parse_identity(bytes, sizeof bytes, &back));
  assert_int_equal(back.product_id, kProductId);
  assert_int_equal(back.firmware_minor, 9);
  assert_string_equal(back.serial, "0005-1234-0042");
  assert_false(parse_identity(bytes, sizeof bytes - 1, &back));
}

// A frame on the wire (MODE_5 unless `use_case_index` says otherwise):
// header, then a payload of a known pattern.
struct WireFrame {
  std::vector<std::uint8_t> bytes;
};
WireFrame make_frame(std::uint32_t sequence, std::uint8_t use_case_index = 5) {
  std::size_t use_case_count = 0;
  const std::uint8_t images = hal::use_cases(&use_case_count)[use_case_index].raw_frames;
  FrameHeader h;
  h.sequence = sequence;
  h.use_case_index = use_case_index;
  h.raw_images = images;
  h.width_px = tof::kWidthPx;
  h.height_px = tof::kHeightPx;
  h.payload_bytes = static_cast<std::uint32_t>(images * tof::kPixels * 2);
  h.exposure_us = 400;
  h.temperature_centi_c = 3650;
  WireFrame f;
  f.bytes.resize(kFrameHeaderBytes + h.payload_bytes);
  for (std::size_t i = 0; i < h.payload_bytes / 2; ++i) {
    put_u16(&f.bytes[kFrameHeaderBytes + 2 * i],
            static_cast<std::uint16_t>((i + sequence) & 0xFFF));
  }
  h.payload_checksum = fletcher32(&f.bytes[kFrameHeaderBytes], h.payload_bytes);
  encode_frame_header(h, f.bytes.data());
  return f;
}

// Feeds a frame in transfers of `transfer` bytes, as the camera would
// send it (the last one short, or a zero-length one after a full last).
// Feeds a frame in transfers of `transfer` bytes, as the camera would
// send it: the last one short, or a zero-length one after a full last
// one. The result: kFrameReady if the frame was handed on, else kDropped
// if anything was dropped on the way.
AssemblyEvent feed(FrameAssembler* a, const WireFrame& f, std::size_t transfer,
                   std::size_t cut_at = 0) {
  const std::size_t total = cut_at != 0 ? cut_at : f.bytes.size();
  bool ready = false, dropped = false;
  for (std::size_t sent = 0; sent < total;) {
    const std::size_t n = total - sent < transfer ? total - sent : transfer;
    const AssemblyEvent e = a->on_transfer(&f.bytes[sent], n, transfer);
    ready = ready || e == AssemblyEvent::kFrameReady;
    dropped = dropped || e == AssemblyEvent::kDropped;
    sent += n;
  }
  if (total % transfer == 0)
    dropped = dropped || a->on_transfer(nullptr, 0, transfer) != AssemblyEvent::kNone;
  return ready     ? AssemblyEvent::kFrameReady
         : dropped ? AssemblyEvent::kDropped
                   : AssemblyEvent::kNone;
}

void test_assembler_good_frames(void**) {
  auto raw = std::make_unique<tof::RawFrame>();
  FrameAssembler a(raw.get());
  assert_int_equal(feed(&a, make_frame(0), 65536), AssemblyEvent::kFrameReady);
  assert_int_equal(raw->mode, tof::Mode::kMode5);
  assert_int_equal(raw->exposure_us, 400);
  assert_near(raw->sensor_temperature_c, 36.5, 1e-4);
  assert_int_equal(raw->image(4)[10], (4 * tof::kPixels + 10) & 0xFFF);
  // A transfer size that divides the frame: ended by a zero-length packet.
  const std::size_t exact = make_frame(1).bytes.size() / 8;
  assert_int_equal(exact % 8, 0);  // 383104 / 8 = 47888
  assert_int_equal(feed(&a, make_frame(1), exact), AssemblyEvent::kFrameReady);
  assert_int_equal(a.counts().zero_length_transfers, 1);
  // A gap: delivered, the missed frames counted.
  assert_int_equal(feed(&a, make_frame(4), 65536), AssemblyEvent::kFrameReady);
  assert_int_equal(a.counts().frames_missed, 2);
  assert_int_equal(a.counts().frames_complete, 3);
  assert_int_equal(a.counts().dropped(), 0);
}

void test_assembler_drops(void**) {
  auto raw = std::make_unique<tof::RawFrame>();
  FrameAssembler a(raw.get());
  assert_int_equal(feed(&a, make_frame(10), 65536), AssemblyEvent::kFrameReady);
  // Short: ended early by a short transfer.
  assert_int_equal(feed(&a, make_frame(11), 65536, 100000), AssemblyEvent::kDropped);
  assert_int_equal(a.counts().frames_short, 1);
  // Corrupt: a payload bit flipped.
  WireFrame bad = make_frame(12);
  bad.bytes[5000] ^= 0x01;
  assert_int_equal(feed(&a, bad, 65536), AssemblyEvent::kDropped);
  assert_int_equal(a.counts().frames_corrupt, 1);
  // Out of order: an earlier sequence number than the last handed on.
  assert_int_equal(feed(&a, make_frame(9), 65536), AssemblyEvent::kDropped);
  assert_int_equal(a.counts().frames_out_of_order, 1);
  // A stray transfer where a header should be: not a frame, counted apart.
  std::uint8_t junk[1024] = {};
  assert_int_equal(a.on_transfer(junk, sizeof junk, 65536), AssemblyEvent::kDiscarded);
  assert_int_equal(a.counts().frames_bad_header, 0);
  assert_int_equal(a.counts().transfers_discarded, 1);
  assert_int_equal(a.counts().last_header_error, ParseStatus::kBadMagic);
  // A frame whose end was lost, then the next frame's header: the first is
  // short, the second arrives.
  WireFrame first = make_frame(13);
  assert_int_equal(a.on_transfer(first.bytes.data(), 65536, 65536), AssemblyEvent::kNone);
  assert_int_equal(feed(&a, make_frame(14), 65536), AssemblyEvent::kFrameReady);
  assert_int_equal(a.counts().frames_short, 2);
  // A header whose sizes do not fit its use case.
  WireFrame wrong = make_frame(15);
  wrong.bytes[17] = 9;  // MODE_9's image count on a MODE_5 use case
  put_u32(&wrong.bytes[60], crc32(wrong.bytes.data(), 60));
  assert_int_equal(a.on_transfer(wrong.bytes.data(), 65536, 65536), AssemblyEvent::kDropped);
  assert_int_equal(a.counts().last_header_error, ParseStatus::kBadSize);
  assert_int_equal(a.counts().frames_bad_header, 1);
  // The rest of that frame's transfers are skipped, not counted again.
  assert_int_equal(
      feed(&a, WireFrame{std::vector<std::uint8_t>(wrong.bytes.begin() + 65536, wrong.bytes.end())},
           65536),
      AssemblyEvent::kNone);
  assert_int_equal(a.counts().frames_bad_header, 1);
  assert_int_equal(a.counts().transfers_discarded, 1);
  // Exposures outside the use case's range (MODE_5_45FPS_500: 1 to 500 us).
  for (const std::uint32_t exposure_us : {0u, 501u, 0xFFFFFFFFu}) {
    WireFrame overexposed = make_frame(16);
    put_u32(&overexposed.bytes[24], exposure_us);
    put_u32(&overexposed.bytes[60], crc32(overexposed.bytes.data(), 60));
    assert_int_equal(feed(&a, overexposed, 65536), AssemblyEvent::kDropped);
    assert_int_equal(a.counts().last_header_error, ParseStatus::kBadExposure);
  }
  assert_int_equal(a.counts().frames_bad_header, 4);
  assert_string_equal(pico_flexx::to_string(ParseStatus::kBadExposure), "BAD_EXPOSURE");
  // A capture time past 2^62 us.
  WireFrame far_future = make_frame(16);
  put_u32(&far_future.bytes[36], 0x40000000u);  // the stamp's high word: 2^62
  put_u32(&far_future.bytes[60], crc32(far_future.bytes.data(), 60));
  assert_int_equal(feed(&a, far_future, 65536), AssemblyEvent::kDropped);
  assert_int_equal(a.counts().last_header_error, ParseStatus::kBadTime);
  assert_int_equal(a.counts().frames_bad_header, 5);
  // After all that, good frames still arrive.
  assert_int_equal(feed(&a, make_frame(16), 65536), AssemblyEvent::kFrameReady);
  // Where a frame begins (its capture time's arrival): at its header's
  // transfer, also when that header cuts short a frame that lost its end;
  // never at a transfer inside a frame.
  const WireFrame cut = make_frame(17), next = make_frame(18);
  assert_int_equal(a.on_transfer(cut.bytes.data(), 65536, 65536), AssemblyEvent::kNone);
  assert_true(a.started_frame());
  assert_int_equal(a.on_transfer(cut.bytes.data() + 65536, 65536, 65536), AssemblyEvent::kNone);
  assert_false(a.started_frame());
  assert_int_equal(a.on_transfer(next.bytes.data(), 65536, 65536), AssemblyEvent::kDropped);
  assert_true(a.started_frame());
}

// Each refused frame counts once, however many transfers it spans: three
// MODE_9 frames (11 transfers of 64 KB each) with a bad header CRC, three
// with a bad payload, three whose end overran. The frames refused are
// among the frames missed, never more; stray transfers are neither.
void test_assembler_counts_once_per_frame(void**) {
  constexpr std::uint8_t kMode9 = 3;  // MODE_9_25FPS_450
  constexpr std::size_t kTransfer = 65536;
  auto raw = std::make_unique<tof::RawFrame>();
  FrameAssembler a(raw.get());
  std::uint32_t sequence = 100;
  assert_int_equal(feed(&a, make_frame(sequence++, kMode9), kTransfer), AssemblyEvent::kFrameReady);
  const std::size_t transfers_per_frame =
      (make_frame(0, kMode9).bytes.size() + kTransfer - 1) / kTransfer;
  assert_int_equal(transfers_per_frame, 11);
  for (int i = 0; i < 3; ++i) {
    WireFrame bad_crc = make_frame(sequence++, kMode9);
    bad_crc.bytes[40] ^= 0x01;  // in the header, after its CRC was computed
    assert_int_equal(feed(&a, bad_crc, kTransfer), AssemblyEvent::kDropped);
  }
  assert_int_equal(a.counts().frames_bad_header, 3);
  assert_int_equal(a.counts().last_header_error, ParseStatus::kBadCrc);
  for (int i = 0; i < 3; ++i) {
    WireFrame corrupt = make_frame(sequence++, kMode9);
    corrupt.bytes[300000] ^= 0x01;
    assert_int_equal(feed(&a, corrupt, kTransfer), AssemblyEvent::kDropped);
  }
  assert_int_equal(a.counts().frames_corrupt, 3);
  // Overrun: a MODE_5 header on a MODE_9 frame's bytes, which run past it.
  for (int i = 0; i < 3; ++i) {
    WireFrame longer = make_frame(sequence, kMode9);
    const WireFrame mode5 = make_frame(sequence++);
    std::copy(mode5.bytes.begin(), mode5.bytes.begin() + kFrameHeaderBytes, longer.bytes.begin());
    assert_int_equal(feed(&a, longer, kTransfer), AssemblyEvent::kDropped);
  }
  assert_int_equal(a.counts().frames_overrun, 3);
  // Stray transfers between frames, a full one and a short one.
  std::vector<std::uint8_t> junk(kTransfer, 0x07);
  assert_int_equal(a.on_transfer(junk.data(), kTransfer, kTransfer), AssemblyEvent::kDiscarded);
  assert_int_equal(a.on_transfer(junk.data(), 100, kTransfer), AssemblyEvent::kDiscarded);
  assert_int_equal(feed(&a, make_frame(sequence++, kMode9), kTransfer), AssemblyEvent::kFrameReady);
  const AssemblerCounts& c = a.counts();
  assert_int_equal(c.dropped(), 9);
  assert_int_equal(c.transfers_discarded, 2);
  assert_int_equal(c.frames_missed, 9);
  assert_true(c.dropped() <= c.frames_missed);
  assert_int_equal(c.frames_complete, 2);
  assert_int_equal(c.transfers, 11 * 11 + 2);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_checksums),
      cmocka_unit_test(test_command_round_trip_and_refusals),
      cmocka_unit_test(test_reply_matching),
      cmocka_unit_test(test_identity_round_trip),
      cmocka_unit_test(test_assembler_good_frames),
      cmocka_unit_test(test_assembler_drops),
      cmocka_unit_test(test_assembler_counts_once_per_frame),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
