// PNG writer for RGB images (8 bits a channel, no interlace), with zlib's deflate. Used for preview.png.
#pragma once

#include <filesystem>

#include "nodes/core/image.h"

namespace scanfill {

// Writes `image` to `path` atomically. Throws IoError naming the file on failure.
void write_png(const std::filesystem::path& path, const Image& image);

}  // namespace scanfill
