// BLF read object by object: the file's top-level objects (log containers, each inflated alone)
// feed one stream of inner objects; an object may continue from one container into the next.
#include "meter/controller/input/blf_log.hpp"

#include <libdeflate.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>

#include "meter/controller/input/blf_log_writer.hpp"
#include "meter/controller/input/candump_line.hpp"
#include "meter/controller/input/log_fields.hpp"

namespace meter::controller {
namespace {

std::uint32_t blf_u16(const char* p) {
  return static_cast<std::uint32_t>(static_cast<unsigned char>(p[0])) | static_cast<std::uint32_t>(static_cast<unsigned char>(p[1])) << 8;
}
std::uint32_t blf_u32(const char* p) { return blf_u16(p) | blf_u16(p + 2) << 16; }
std::uint64_t blf_u64(const char* p) { return blf_u32(p) | static_cast<std::uint64_t>(blf_u32(p + 4)) << 32; }

constexpr std::size_t kBlfObjectHeader = 16;           // "LOBJ", header size, header version, object size, type
constexpr std::uint32_t kBlfLargestObject = 64u << 20;  // larger is a damaged size field, not an object

std::string blf_type_name(std::uint32_t type) {
  switch (type) {
    case kBlfCanMessage: return "CAN_MESSAGE";
    case kBlfLogContainer: return "LOG_CONTAINER";
    case kBlfCanErrorExt: return "CAN_ERROR_EXT";
    case kBlfCanMessage2: return "CAN_MESSAGE2";
    case kBlfCanFdMessage: return "CAN_FD_MESSAGE";
    case kBlfCanFdMessage64: return "CAN_FD_MESSAGE_64";
    default: return "object type " + std::to_string(type);
  }
}

class BlfReader : public LogSource {
 public:
  explicit BlfReader(std::istream& in) : in_(in), log_(window()), inflater_(libdeflate_alloc_decompressor()) { watch(in); }

 private:
  std::istream& in_;
  ParsedLog& log_;
  std::uint64_t offset_ = 0;  // of the next top-level object
  std::uint64_t at_ = 0;      // of the top-level object whose inner objects are being read
  std::int64_t start_ns_ = 0;
  std::string body_, inner_;  // a top-level object's bytes; the inner objects not yet read
  std::size_t pos_ = 0;       // in inner_
  bool started_ = false, ok_ = true;
  // zlib containers are inflated by libdeflate: a container is inflated whole (its size is in its
  // header), which libdeflate does several times faster than zlib's streaming inflate, Adler-32
  // checked alike.
  struct FreeInflater {
    void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
  };
  std::unique_ptr<libdeflate_decompressor, FreeInflater> inflater_;

  // One inner object, else the next top-level object (a container is inflated whole, its objects
  // then read one per call): the window holds one object's frame at most.
  bool read_more() override {
    if (!started_) return started_ = true, header();
    if (!ok_) return false;
    for (;;) {
      const int got = inner_object();
      if (got > 0) return true;
      if (got < 0 || !top_object()) break;
    }
    if (ok_ && inner_.size() - pos_ >= kBlfObjectHeader)
      fail("byte offset " + std::to_string(offset_) + ": the file ends inside an object of its last container");
    ok_ = false;
    return false;
  }

  void fail(std::string why) {  // a header error is record 0, an object's its number
    log_.bad_lines.push_back({log_.lines, std::move(why)});
    ok_ = false;
  }

  std::size_t read_bytes(std::string& into, std::size_t n) {
    into.resize(n);
    in_.read(into.data(), static_cast<std::streamsize>(n));
    into.resize(static_cast<std::size_t>(in_.gcount()));
    return into.size();
  }

  bool header() {
    std::string h;
    if (read_bytes(h, 8) < 8 || h.compare(0, 4, "LOGG") != 0) return fail("byte offset 0: expected the BLF signature 'LOGG' and the header size"), false;
    const std::uint32_t size = blf_u32(h.data() + 4);
    if (size < 72 || size > 65536) return fail("byte offset 4: header size " + std::to_string(size) + ", expected 72..65536"), false;
    std::string rest;
    if (read_bytes(rest, size - 8) < size - 8) return fail("byte offset " + std::to_string(8 + rest.size()) + ": the file ends inside its header"), false;
    const char* st = rest.data() + 32;  // SYSTEMTIME start: year, month, weekday, day, hour, minute, second, ms
    const auto start = local_time_ns(static_cast<int>(blf_u16(st)), static_cast<int>(blf_u16(st + 2)), static_cast<int>(blf_u16(st + 6)),
                                     static_cast<int>(blf_u16(st + 8)), static_cast<int>(blf_u16(st + 10)), static_cast<int>(blf_u16(st + 12)),
                                     static_cast<std::int64_t>(blf_u16(st + 14) % 1000) * 1000000);
    start_ns_ = start.value_or(0);  // no start date: the objects' own times from 0
    offset_ = size;
    return true;
  }

  std::string where(std::uint64_t at, std::uint32_t type) const {
    return "byte offset " + std::to_string(at) + " (object " + std::to_string(log_.lines) + ", " + blf_type_name(type) + ")";
  }

  bool top_object() {
    std::string base;
    const std::size_t got = read_bytes(base, kBlfObjectHeader);
    if (got == 0) return false;
    ++log_.lines;
    if (got < kBlfObjectHeader) return fail("byte offset " + std::to_string(offset_) + ": the file ends inside an object header"), false;
    if (base.compare(0, 4, "LOBJ") != 0) return fail("byte offset " + std::to_string(offset_) + ": expected an object signature 'LOBJ'"), false;
    const std::uint32_t size = blf_u32(base.data() + 8), type = blf_u32(base.data() + 12);
    if (size < kBlfObjectHeader || size > kBlfLargestObject)
      return fail(where(offset_, type) + ": object size " + std::to_string(size) + ", expected 16.." + std::to_string(kBlfLargestObject)), false;
    if (read_bytes(body_, size - kBlfObjectHeader) < size - kBlfObjectHeader)
      return fail(where(offset_, type) + ": truncated, " + std::to_string(size) + " bytes expected, the file ends after " +
                  std::to_string(kBlfObjectHeader + body_.size())), false;
    std::string padding;
    read_bytes(padding, size % 4);  // Vector's writers pad each object by its size modulo 4
    at_ = offset_;
    offset_ += size + size % 4;
    if (type != kBlfLogContainer) {  // an object outside any container: read as it stands
      compact();
      inner_ += base;
      inner_ += body_;
      return true;
    }
    return container(at_);
  }

  void compact() {
    inner_.erase(0, pos_);
    pos_ = 0;
  }

  bool container(std::uint64_t at) {
    if (body_.size() < 16) return fail(where(at, kBlfLogContainer) + ": expected the 16-byte container header"), false;
    const std::uint32_t method = blf_u16(body_.data()), size = blf_u32(body_.data() + 8);
    if (size > kBlfLargestObject) return fail(where(at, kBlfLogContainer) + ": uncompressed size " + std::to_string(size) + " is beyond any container"), false;
    compact();
    const std::size_t have = inner_.size();
    if (method == 0) {
      inner_.append(body_, 16, std::string::npos);
      return true;
    }
    if (method != 2) return fail(where(at, kBlfLogContainer) + ": compression method " + std::to_string(method) + ", expected 0 (none) or 2 (zlib)"), false;
    inner_.resize(have + size);
    if (!inflater_) return fail(where(at, kBlfLogContainer) + ": the zlib decompressor cannot start (out of memory)"), false;
    std::size_t out = 0;
    const libdeflate_result r = libdeflate_zlib_decompress(inflater_.get(), body_.data() + 16, body_.size() - 16, inner_.data() + have, size, &out);
    if (r != LIBDEFLATE_SUCCESS) inner_.resize(have);
    if (r == LIBDEFLATE_INSUFFICIENT_SPACE) return fail(where(at, kBlfLogContainer) + ": corrupt zlib data (holds more than " + std::to_string(size) + " bytes)"), false;
    if (r != LIBDEFLATE_SUCCESS) return fail(where(at, kBlfLogContainer) + ": corrupt zlib data (a bad block, checksum or end)"), false;
    inner_.resize(have + out);
    if (out != size) return fail(where(at, kBlfLogContainer) + ": inflates to " + std::to_string(out) + " bytes, its header says " + std::to_string(size)), false;
    return true;
  }

  // The next complete inner object read: 1; none complete (one cut by the container's end waits
  // for the next container): 0; a broken one: -1.
  int inner_object() {
    const std::uint64_t at = at_;
    std::size_t skip = 0;  // padding between objects
    while (skip < 8 && pos_ + skip + 4 <= inner_.size() && inner_.compare(pos_ + skip, 4, "LOBJ") != 0) ++skip;
    if (pos_ + skip + kBlfObjectHeader > inner_.size()) return 0;
    const char* h = inner_.data() + pos_ + skip;
    const std::uint32_t type = blf_u32(h + 12), size = blf_u32(h + 8);
    ++log_.lines;
    if (skip == 8) return fail(where(at, kBlfLogContainer) + ", inner offset " + std::to_string(pos_) + ": expected an object signature 'LOBJ'"), -1;
    if (size < kBlfObjectHeader || size > kBlfLargestObject)
      return fail(where(at, type) + ", inner offset " + std::to_string(pos_ + skip) + ": object size " + std::to_string(size)), -1;
    pos_ += skip;
    if (pos_ + size > inner_.size()) {  // continues in the next container
      --log_.lines;
      return 0;
    }
    object(std::string_view(h, size), at);
    pos_ += size;
    return 1;
  }

  void object(std::string_view o, std::uint64_t at) {
    const std::uint32_t header_size = blf_u16(o.data() + 4), version = blf_u16(o.data() + 6), type = blf_u32(o.data() + 12);
    const std::size_t need = version == 2 ? 40 : 32;
    if ((version != 1 && version != 2) || header_size < need || header_size > o.size())
      return log_.bad_lines.push_back({log_.lines, where(at, type) + ": object header version " + std::to_string(version) + " of " +
                                                       std::to_string(header_size) + " bytes, expected version 1 (32) or 2 (40)"});
    const std::uint32_t flags = blf_u32(o.data() + 16);
    const std::uint64_t t = blf_u64(o.data() + 24);
    const std::uint64_t unit = flags == 1 ? 10000 : 1;  // 10 us or 1 ns
    if (t > static_cast<std::uint64_t>(INT64_MAX - std::max<std::int64_t>(start_ns_, 0)) / unit)
      return log_.bad_lines.push_back({log_.lines, where(at, type) + ": time " + std::to_string(t) + " is beyond the nanosecond clock (year 2262)"});
    CanFrame f;
    f.timestamp_ns = start_ns_ + static_cast<std::int64_t>(t * unit);
    const std::string_view p = o.substr(header_size);
    std::string why;
    if (!frame(type, p, f, why)) {
      if (why.empty()) ++log_.skipped;
      else log_.bad_lines.push_back({log_.lines, where(at, type) + ": " + why});
      return;
    }
    log_.frames.push_back(f);
  }

  // The frame an object holds: false with `why` empty for kinds that hold none.
  static bool frame(std::uint32_t type, std::string_view p, CanFrame& f, std::string& why) {
    const char* d = p.data();
    auto too_short = [&](std::size_t n) { return p.size() < n ? (why = "expected " + std::to_string(n) + " payload bytes, got " + std::to_string(p.size()), true) : false; };
    std::uint32_t channel = 0, raw_id = 0;
    if (type == kBlfCanMessage || type == kBlfCanMessage2) {
      if (too_short(16)) return false;
      channel = blf_u16(d), raw_id = blf_u32(d + 4);
      f.rtr = (static_cast<unsigned char>(d[2]) & 0x80) != 0;
      const unsigned dlc = static_cast<unsigned char>(d[3]) & 15;
      f.len = static_cast<std::uint8_t>(dlc > 8 ? 8 : dlc);
      if (dlc > 8) f.len8_dlc = static_cast<std::uint8_t>(dlc);
      std::copy(d + 8, d + 16, f.data.begin());
    } else if (type == kBlfCanFdMessage) {
      if (too_short(84)) return false;
      channel = blf_u16(d), raw_id = blf_u32(d + 4);
      const unsigned fd_flags = static_cast<unsigned char>(d[13]), valid = static_cast<unsigned char>(d[14]);
      f.rtr = (static_cast<unsigned char>(d[2]) & 0x80) != 0;
      f.fd = (fd_flags & 1) != 0;
      if (!set_length(f, valid, static_cast<unsigned char>(d[3]) & 15, why)) return false;
      f.fd_flags = static_cast<std::uint8_t>(f.fd ? ((fd_flags & 2) ? kCanFdBrs : 0) | ((fd_flags & 4) ? kCanFdEsi : 0) : 0);
      std::copy(d + 20, d + 20 + f.len, f.data.begin());
    } else if (type == kBlfCanFdMessage64) {
      if (too_short(40)) return false;
      channel = static_cast<unsigned char>(d[0]), raw_id = blf_u32(d + 4);
      const std::uint32_t flags = blf_u32(d + 12);
      const unsigned valid = static_cast<unsigned char>(d[2]);
      f.rtr = (flags & 0x10) != 0;
      f.fd = (flags & 0x1000) != 0;
      if (!set_length(f, valid, static_cast<unsigned char>(d[1]) & 15, why) || too_short(40 + (f.rtr ? 0 : f.len))) return false;
      f.fd_flags = static_cast<std::uint8_t>(f.fd ? ((flags & 0x2000) ? kCanFdBrs : 0) | ((flags & 0x4000) ? kCanFdEsi : 0) : 0);
      if (!f.rtr) std::copy(d + 40, d + 40 + f.len, f.data.begin());
    } else if (type == kBlfCanErrorExt) {
      if (too_short(32)) return false;
      f.error = true;  // the object names the frame it broke, not a SocketCAN error class: id 0
      channel = blf_u16(d);
    } else {
      return false;
    }
    if (channel == 0 || channel > 255) return why = "channel " + std::to_string(channel) + ", expected 1..255", false;
    f.channel = static_cast<std::uint8_t>(channel);
    if (f.error) return true;
    f.extended = (raw_id & 0x80000000u) != 0;
    f.id = raw_id & 0x1FFFFFFFu;
    if (!f.extended && f.id > 0x7FF) return why = "standard id " + std::to_string(f.id) + " above 0x7FF", false;
    return true;
  }

  // A CAN FD object's length: its valid bytes (remote frames: from the DLC).
  static bool set_length(CanFrame& f, unsigned valid, unsigned dlc, std::string& why) {
    const unsigned len = f.rtr ? (dlc > 8 ? 8 : dlc) : valid;
    if (f.fd ? !is_valid_fd_len(len) : len > 8) return why = std::to_string(len) + " data bytes is not a " + (f.fd ? "CAN FD" : "classic CAN") + " length", false;
    f.len = static_cast<std::uint8_t>(len);
    if (!f.fd && !f.rtr && dlc > 8 && len == 8) f.len8_dlc = static_cast<std::uint8_t>(dlc);
    return true;
  }
};

}  // namespace

std::unique_ptr<LogSource> open_blf_log(std::istream& in) { return std::make_unique<BlfReader>(in); }

ParsedLog read_blf_log(std::istream& in) { return read_whole_log(*open_blf_log(in)); }

bool sniff_blf_log(std::string_view head) { return head.substr(0, 4) == "LOGG"; }

const LogFormat& blf_log_format() {
  static constexpr std::string_view kExtensions[] = {".blf"};
  static const LogFormat format{"blf", "LOGG (binary)", kExtensions, sniff_blf_log, open_blf_log, write_blf_log};
  return format;
}

}  // namespace meter::controller
