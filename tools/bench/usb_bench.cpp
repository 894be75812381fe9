// The Pico Flexx USB driver's CPU cost per frame, without the USB: frame
// reassembly (header checks, copying the payload into the raw frame, the
// payload checksum, the sequence check) over MODE_5 and MODE_9 frames cut
// into the driver's 64 KB transfers, and the time from a frame's last
// transfer to the frame being ready for the listener.
//
// Targets: streaming plus reassembly <= 5 % of a core at 45 fps
// (that is <= 1.1 ms a frame); last transfer to listener, median <= 2 ms.
#include <benchmark/benchmark.h>

#include <chrono>
#include <memory>
#include <vector>

#include "pico_flexx/frame_assembler.hpp"
#include "pico_flexx/usb_protocol.hpp"

namespace {

constexpr std::size_t kTransferBytes = 64 * 1024;

// A frame as it arrives: header and payload, in kTransferBytes pieces.
std::vector<std::uint8_t> wire_frame(std::uint8_t use_case_index, std::uint8_t raw_images,
                                     std::uint32_t sequence) {
  pico_flexx::FrameHeader h;
  h.sequence = sequence;
  h.use_case_index = use_case_index;
  h.raw_images = raw_images;
  h.width_px = tof::kWidthPx;
  h.height_px = tof::kHeightPx;
  h.payload_bytes = static_cast<std::uint32_t>(raw_images * tof::kPixels * 2);
  h.exposure_us = 400;
  std::vector<std::uint8_t> bytes(pico_flexx::kFrameHeaderBytes + h.payload_bytes);
  for (std::size_t i = 0; i < h.payload_bytes / 2; ++i) {
    pico_flexx::put_u16(&bytes[pico_flexx::kFrameHeaderBytes + 2 * i],
                        static_cast<std::uint16_t>((i * 37u) & 0xFFFu));
  }
  h.payload_checksum =
      pico_flexx::fletcher32(&bytes[pico_flexx::kFrameHeaderBytes], h.payload_bytes);
  pico_flexx::encode_frame_header(h, bytes.data());
  return bytes;
}

void set_sequence(std::vector<std::uint8_t>* frame, std::uint32_t sequence) {
  pico_flexx::put_u32(&(*frame)[8], sequence);
  pico_flexx::put_u32(&(*frame)[60], pico_flexx::crc32(frame->data(), 60));
}

// Whole frames through the assembler, every transfer timed.
void reassemble(benchmark::State& state, std::uint8_t use_case_index, std::uint8_t raw_images) {
  auto raw = std::make_unique<tof::RawFrame>();
  pico_flexx::FrameAssembler assembler(raw.get());
  std::vector<std::uint8_t> frame = wire_frame(use_case_index, raw_images, 0);
  std::uint32_t sequence = 0;
  for (auto _ : state) {
    state.PauseTiming();
    set_sequence(&frame, sequence++);
    state.ResumeTiming();
    for (std::size_t sent = 0; sent < frame.size(); sent += kTransferBytes) {
      const std::size_t n =
          frame.size() - sent < kTransferBytes ? frame.size() - sent : kTransferBytes;
      benchmark::DoNotOptimize(assembler.on_transfer(&frame[sent], n, kTransferBytes));
    }
  }
  if (assembler.counts().frames_complete != static_cast<std::uint64_t>(state.iterations())) {
    state.SkipWithError("a frame was not reassembled");
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * frame.size()));
}

void BM_ReassembleMode5Frame(benchmark::State& state) {
  reassemble(state, 5, 5);
}
void BM_ReassembleMode9Frame(benchmark::State& state) {
  reassemble(state, 0, 9);
}

// From the callback of a frame's last transfer to the frame being handed
// on (the rest of the frame already in): the last piece's copy, the
// checksum over the whole payload, the sequence check.
void last_transfer_to_ready(benchmark::State& state, std::uint8_t use_case_index,
                            std::uint8_t raw_images) {
  auto raw = std::make_unique<tof::RawFrame>();
  pico_flexx::FrameAssembler assembler(raw.get());
  std::vector<std::uint8_t> frame = wire_frame(use_case_index, raw_images, 0);
  const std::size_t last = (frame.size() - 1) / kTransferBytes * kTransferBytes;
  std::uint32_t sequence = 0;
  for (auto _ : state) {
    set_sequence(&frame, sequence++);
    for (std::size_t sent = 0; sent < last; sent += kTransferBytes) {
      assembler.on_transfer(&frame[sent], kTransferBytes, kTransferBytes);
    }
    const auto t0 = std::chrono::steady_clock::now();
    const pico_flexx::AssemblyEvent e =
        assembler.on_transfer(&frame[last], frame.size() - last, kTransferBytes);
    const auto t1 = std::chrono::steady_clock::now();
    if (e != pico_flexx::AssemblyEvent::kFrameReady) state.SkipWithError("frame not ready");
    state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count());
  }
}

void BM_LastTransferToReadyMode5(benchmark::State& state) {
  last_transfer_to_ready(state, 5, 5);
}
void BM_LastTransferToReadyMode9(benchmark::State& state) {
  last_transfer_to_ready(state, 0, 9);
}

}  // namespace

BENCHMARK(BM_ReassembleMode5Frame)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ReassembleMode9Frame)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LastTransferToReadyMode5)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LastTransferToReadyMode9)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
