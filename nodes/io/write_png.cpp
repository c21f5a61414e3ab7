#include "nodes/io/write_png.h"

#include <zlib.h>

#include <string>

#include "nodes/core/errors.h"
#include "nodes/io/write_ply.h"

namespace scanfill {
namespace {

void put_u32(std::string& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(char((v >> shift) & 0xff));
}

// A chunk: length, type, data, CRC of type and data.
void put_chunk(std::string& out, const char* type, const std::string& data) {
  put_u32(out, std::uint32_t(data.size()));
  const size_t start = out.size();
  out.append(type, 4);
  out += data;
  const auto crc = crc32(0, reinterpret_cast<const Bytef*>(out.data() + start), uInt(out.size() - start));
  put_u32(out, std::uint32_t(crc));
}

}  // namespace

void write_png(const std::filesystem::path& path, const Image& image) {
  if (image.width < 1 || image.height < 1 || image.rgb.size() != size_t(image.width) * size_t(image.height) * 3)
    throw InvariantError("write_png: the image's size does not match its pixels");
  std::string raw;  // each row: filter type 0, then its pixels
  raw.reserve(size_t(image.height) * (1 + 3 * size_t(image.width)));
  for (int y = 0; y < image.height; ++y) {
    raw.push_back('\0');
    raw.append(reinterpret_cast<const char*>(image.rgb.data()) + 3 * size_t(y) * size_t(image.width),
               3 * size_t(image.width));
  }
  uLongf packed_size = compressBound(uLong(raw.size()));
  std::string packed(packed_size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(packed.data()), &packed_size, reinterpret_cast<const Bytef*>(raw.data()),
                uLong(raw.size()), 6) != Z_OK)
    throw IoError(path.string() + ": cannot compress the image");
  packed.resize(packed_size);
  std::string png("\x89PNG\r\n\x1a\n", 8), header;
  put_u32(header, std::uint32_t(image.width));
  put_u32(header, std::uint32_t(image.height));
  header += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, adaptive filters, no interlace
  put_chunk(png, "IHDR", header);
  put_chunk(png, "IDAT", packed);
  put_chunk(png, "IEND", "");
  write_file_atomic(path, png);
}

}  // namespace scanfill
