// Frames to BLF objects, packed into zlib log containers.
#include "meter/controller/input/blf_log_writer.hpp"

#include <zlib.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "meter/controller/input/blf_log.hpp"
#include "meter/controller/input/candump_line.hpp"
#include "meter/controller/input/log_fields.hpp"
#include "meter/controller/input/write_log_chunks.hpp"

namespace meter::controller {
namespace {

void blf_put_le(std::string& out, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) out += static_cast<char>((v >> (8 * i)) & 0xFF);
}

// SYSTEMTIME: year, month, weekday, day, hour, minute, second, milliseconds.
void put_systemtime(std::string& out, std::int64_t ns) {
  const std::int64_t seconds = ns >= 0 ? ns / 1000000000LL : 0;
  const LocalTime t = local_time_of(seconds);
  for (int v : {t.year, t.month, t.weekday, t.day, t.hour, t.minute, t.second, static_cast<int>(ns >= 0 ? ns % 1000000000LL / 1000000 : 0)})
    blf_put_le(out, static_cast<std::uint64_t>(v), 2);
}

void put_blf_object(std::string& out, std::uint32_t type, std::uint64_t time_ns, const std::string& payload) {
  const std::uint32_t size = 32 + static_cast<std::uint32_t>(payload.size());
  out += "LOBJ";
  blf_put_le(out, 32, 2);  // header size
  blf_put_le(out, 1, 2);   // header version 1
  blf_put_le(out, size, 4);
  blf_put_le(out, type, 4);
  blf_put_le(out, 2, 4);  // times in nanoseconds
  blf_put_le(out, 0, 4);  // client index, object version
  blf_put_le(out, time_ns, 8);
  out += payload;
  out.append(size % 4, '\0');
}

void put_blf_frame(std::string& out, const CanFrame& f, std::uint64_t time_ns) {
  const std::uint32_t channel = f.channel ? f.channel : 1;
  const std::uint32_t id = f.id | (f.extended ? 0x80000000u : 0);
  std::string p;
  if (f.error) {
    blf_put_le(p, channel, 2);
    p.append(30, '\0');  // length, flags, ECC, position, DLC, frame length, id, extended flags, data: unknown
    return put_blf_object(out, kBlfCanErrorExt, time_ns, p);
  }
  const std::size_t bytes = f.rtr ? 0 : f.len;
  if (f.fd) {
    blf_put_le(p, channel, 2);
    p += static_cast<char>(f.rtr ? 0x80 : 0);
    p += static_cast<char>(can_fd_len_to_dlc(f.len));
    blf_put_le(p, id, 4);
    blf_put_le(p, 0, 4);  // frame length
    p += '\0';        // bit count
    p += static_cast<char>(1 | ((f.fd_flags & kCanFdBrs) ? 2 : 0) | ((f.fd_flags & kCanFdEsi) ? 4 : 0));
    p += static_cast<char>(bytes);
    p.append(5, '\0');
    p.append(reinterpret_cast<const char*>(f.data.data()), bytes);
    p.append(64 - bytes, '\0');
    return put_blf_object(out, kBlfCanFdMessage, time_ns, p);
  }
  blf_put_le(p, channel, 2);
  p += static_cast<char>(f.rtr ? 0x80 : 0);
  p += static_cast<char>(f.len8_dlc ? f.len8_dlc : f.len);
  blf_put_le(p, id, 4);
  p.append(reinterpret_cast<const char*>(f.data.data()), bytes);
  p.append(8 - bytes, '\0');
  put_blf_object(out, kBlfCanMessage, time_ns, p);
}

}  // namespace

std::size_t write_blf_log(LogSource& frames, std::ostream& out, const LogProgress& progress) {
  constexpr std::size_t kContainer = 128 * 1024;
  const CanFrame* head = frames.peek();
  const std::int64_t first = head ? head->timestamp_ns : 0;
  const std::int64_t start = first - ((first % 1000000) + 1000000) % 1000000;  // the first frame's millisecond
  std::int64_t last = start;
  std::uint64_t file_size = kBlfFileHeaderSize, uncompressed = kBlfFileHeaderSize;
  out << std::string(kBlfFileHeaderSize, '\0');  // the header, written once the sizes are known
  std::string packed;
  // Each chunk of objects packed into one zlib log container.
  auto write_container = [&](const std::string& objects) {
    uLongf packed_size = compressBound(static_cast<uLong>(objects.size()));
    packed.resize(packed_size);
    if (compress2(reinterpret_cast<Bytef*>(packed.data()), &packed_size, reinterpret_cast<const Bytef*>(objects.data()),
                  static_cast<uLong>(objects.size()), Z_DEFAULT_COMPRESSION) != Z_OK)
      throw std::runtime_error("BLF: zlib could not compress a log container");
    std::string c = "LOBJ";
    const std::uint32_t size = 32 + static_cast<std::uint32_t>(packed_size);
    blf_put_le(c, 16, 2);
    blf_put_le(c, 1, 2);
    blf_put_le(c, size, 4);
    blf_put_le(c, kBlfLogContainer, 4);
    blf_put_le(c, 2, 2);  // zlib
    c.append(6, '\0');
    blf_put_le(c, objects.size(), 4);
    c.append(4, '\0');
    c.append(packed.data(), packed_size);
    c.append(size % 4, '\0');
    out.write(c.data(), static_cast<std::streamsize>(c.size()));
    file_size += c.size();
    uncompressed += 32 + objects.size();
  };
  const std::size_t written = write_log_chunks(
      frames, kContainer,
      [&](const CanFrame& f, std::string& objects) {
        put_blf_frame(objects, f, static_cast<std::uint64_t>(f.timestamp_ns > start ? f.timestamp_ns - start : 0));
        last = std::max(last, f.timestamp_ns);
      },
      write_container, progress);
  std::string h = "LOGG";
  blf_put_le(h, kBlfFileHeaderSize, 4);
  h.append(8, '\0');  // application id and version, binary log version
  blf_put_le(h, file_size, 8);
  blf_put_le(h, uncompressed, 8);
  blf_put_le(h, written, 4);
  blf_put_le(h, 0, 4);
  put_systemtime(h, start);
  put_systemtime(h, last);
  out.seekp(0);
  out.write(h.data(), static_cast<std::streamsize>(h.size()));
  out.seekp(0, std::ios::end);
  return written;
}

}  // namespace meter::controller
