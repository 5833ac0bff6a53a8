// Writes the fuzz seed corpus: one valid frame per message type and a few edge cases, so libFuzzer
// starts from inputs that already pass the magic, version and CRC checks.
#include <cstdio>
#include <fstream>
#include <string>

#include "meter/protocol/frame_tag.hpp"
#include "meter/protocol/wire.hpp"

using namespace meter::protocol;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <corpus-dir>\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  auto write = [&](const std::string& name, const std::vector<std::uint8_t>& bytes) {
    std::ofstream out(dir + "/" + name, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!out) {
      std::fprintf(stderr, "cannot write %s/%s\n", dir.c_str(), name.c_str());
      std::exit(1);
    }
  };
  write("hello", encode(Frame{1, 1000, Hello{Role::Publisher, kProtocolVersion, catalog_hash(), 26, 100, "meter-controller", "protocol/catalog/signals.vss.json", 0}}));
  write("hello-view", encode(Frame{1, 1000, Hello{Role::Subscriber, kProtocolVersion, catalog_hash(), 26, 100, "meter-view", "my.vss.json", kHelloTakesCatalog}}));
  Snapshot snap;
  for (const auto& s : catalog()) snap.signals.push_back({s.id, SignalStatus::Valid, s.max, false, ""});
  snap.signals[4].has_text = true;
  snap.signals[4].text = "D\xC3\xA9";
  write("snapshot", encode(Frame{2, 2000, snap}));
  write("snapshot-partial", encode(Frame{2, 2000, Snapshot{false, {{sig::kSpeed, SignalStatus::TimedOut, 0, false, ""}}}}));
  write("delta", encode(Frame{3, 3000, Delta{{{sig::kSpeed, SignalStatus::Valid, 88.5, false, ""},
                                              {sig::kTurnLeft, SignalStatus::Valid, 1, false, ""}}}}));
  write("delta-text", encode(Frame{4, 3000, Delta{{{sig::kTrip, SignalStatus::Invalid, -1.5, true, "trip A"}}}}));
  write("catalog", encode(Frame{2, 1500, CatalogChunk{catalog_hash(), 0, 1,
      R"({"Vehicle": {"type": "branch", "children": {"Speed": {"type": "sensor", "datatype": "float", "min": 0, "max": 300, "meter_id": 1}}}})"}}));
  write("heartbeat", encode(Frame{5, 4000, Heartbeat{}}));
  write("status", encode(Frame{6, 5000, Status{600, 5, 1}}));
  write("close", encode(Frame{7, 6000, Close{CloseReason::CatalogMismatch, "catalog hash differs"}}));
  // Several frames back to back: exercises the stream path.
  std::vector<std::uint8_t> stream;
  encode(Frame{1, 1, Hello{Role::Publisher, kProtocolVersion, catalog_hash(), 26, 100, "c", "", 0}}, stream);
  encode(Frame{2, 2, Delta{{{sig::kSpeed, SignalStatus::Valid, 1, false, ""}}}}, stream);
  encode(Frame{3, 3, Heartbeat{}}, stream);
  write("stream", stream);
  // An authenticated link's frames: a HELLO naming its key and nonce, tagged DELTA and HEARTBEAT.
  FrameKey key;
  for (std::size_t i = 0; i < key.bytes.size(); ++i) key.bytes[i] = static_cast<std::uint8_t>(i + 1);
  Hello keyed{Role::Publisher, kProtocolVersion, catalog_hash(), 26, 100, "meter-controller", "", 0};
  keyed.key_id = 1;
  for (std::size_t i = 0; i < keyed.nonce.size(); ++i) keyed.nonce[i] = static_cast<std::uint8_t>(0xA0 + i);
  write("hello-keyed", encode(Frame{1, 1000, keyed}, &key));
  std::vector<std::uint8_t> tagged;
  encode(Frame{2, 2, Delta{{{sig::kSpeed, SignalStatus::Valid, 61.5, false, ""}}}}, tagged, &key);
  encode(Frame{3, 3, Heartbeat{}}, tagged, &key);
  write("stream-tagged", tagged);
  auto bad = encode(Frame{1, 1, Heartbeat{}});
  bad[4] = kProtocolVersion + 1;
  write("bad-version", bad);
  return 0;
}
