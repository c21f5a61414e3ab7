// An RGB image in memory (the preview's panels, nodes/render), as write_png writes it (nodes/io).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace scanfill {

using Rgb = std::array<std::uint8_t, 3>;

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // row-major, top row first, 3 bytes a pixel
};

}  // namespace scanfill
